#include "metrics/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>

#include "bus/core.h"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "metrics/track_association.h"

namespace evade::metrics {

namespace {

// What a run achieved: goal, clearance, contacts, success.
constexpr const char* kOutcomeRules = R"(Rules (times in seconds since the first SIM_TRUTH unless stated):
- first motion: the first SIM_TRUTH with |v| above motion_threshold_mps.
- reached_goal: the robot centre comes within the scenario's goal
  tolerance of the goal; time_to_goal_s runs from first motion to then.
  timed_out: the goal was not reached within the scenario's duration_s.
- min_dist_m: the smallest 2D clearance between the footprint rectangle
  and any obstacle (cylinder = circle, box = oriented rectangle) over the
  whole run up to the goal; collided: that clearance reached 0.
- contacts: each episode of consecutive SIM_TRUTH samples (up to the goal)
  in which the footprint overlaps one obstacle (clearance <= 0) is one
  contact: obstacle_id, t_start_s, t_end_s, max_penetration_m (largest
  -clearance), robot_speed_mps (|v| at t_start_s) and approach_speed_mps:
  the velocity of the robot's own rigid motion (v along its heading plus
  omega x lever arm; not relative to the obstacle) at the footprint point
  closest to the obstacle, projected on the unit vector from that point to
  the obstacle's closest point, both taken in the last sample before the
  contact (at a first sample that already overlaps: towards the obstacle's
  centre), the velocity at t_start_s. at_fault: approach_speed_mps above
  fault_approach_speed_mps. Simulated movers do not avoid the robot, so a
  mover walking into a robot that stands or backs away is a contact not at
  fault. collisions_at_fault / collisions_not_at_fault count the contacts;
  at_fault: any contact at fault.
- success: reached_goal, not timed_out, and no contact at fault.
)";

// The local map, dynamic obstacles and the speed variance.
constexpr const char* kWindowRules = R"(- local map: the square of side local_map_size_m centred on the robot,
  aligned with the world axes (as the elevation map is).
- a dynamic obstacle is one whose true speed exceeds
  dynamic_speed_threshold_mps at some point of the run.
- speed_var: population variance of the robot's true linear speed over the
  SIM_TRUTH samples, after first motion and before the goal, at which some
  moving dynamic obstacle's centre is inside the local map.
)";

// The reaction time by counterfactual replay.
constexpr const char* kReactionRules = R"(- reaction_time_s, the same rule for every planner mode: for each dynamic
  obstacle, t_enter = the first time its centre is inside the local map
  while it moves, t_leave the last. Its perception tracks: every track in
  every obstacle_list_t and prediction_list_t message of the log votes,
  per message, for the true obstacle whose shape (surface; 0 inside) is
  nearest its centre, or for none if that is farther than
  react_match_radius_m. Its first vote makes its owner; another takes over
  once it has had all its votes for react_owner_switch_s, from the first
  of them (a walker's track can stay on the bin it passed, two walkers'
  tracks can swap). The planner core is then run again over the log's
  recorded inputs (the channels it subscribes to, each message when it
  arrived; the run's planner config, the mode of the log's PLAN, latency
  measurement off): once as recorded (the reference) and once per
  obstacle with its tracks removed from every obstacle_list_t and
  prediction_list_t message of a time when they were the obstacle. As the
  recorded planner, the replayed one is busy during a planning cycle, for
  base + per_iteration x (its Ceres iterations) fitted by least squares
  to the log's PLANs (solve_time_us > 0; exact for a lockstep run), and
  of what arrives meanwhile it handles only the newest message of each
  channel it conflates (PlannerCore::conflated_inputs()). A plan differs
  when its positions and the reference plan's of the same cycle (same
  odometry utime; if the reference made no plan from that odometry, its
  last plan before it) are more than react_plan_diff_m apart at some time
  both cover (at the same times: step against step in the same cycle).
  t_react = the utime of the first
  cycle from t_enter to t_until = min(t_leave, t_enter + react_max_s)
  whose plan differs; t_change = the first up to t_until whose plan
  differs (before t_enter when the planner saw the obstacle earlier than
  the paper's window would let it). reaction_time_s: the mean of
  t_react - t_enter over obstacles that got one; the others (no change,
  or never tracked) are counted in reaction_missed. `reactions` lists
  each obstacle's figures.
  replay_plans_compared / _differing / replay_max_plan_diff_m: how the
  reference replay agrees with the recorded PLANs; the counterfactual is
  compared with the reference, not with the recorded plans. Lockstep runs
  (paper_sim, generated crowd and doorway scenes, a ten-walker street)
  agreed exactly; without the compute time a long cycle (106 ms) made the
  recorded planner skip predictions that the replay used, and 2-9 plans
  of 270-740 differed. A live run's planner may also miss messages the
  logger heard (a live paper_sim run: its first 9 plans were NO_ROUTE, it
  missed the first ROUTE) and its solve times are noisy.
  With --no-reaction the replay is skipped and reaction_time_s,
  reaction_missed and reactions are null. The replay's cost grows with
  the obstacles and how late they come: about 2 s of CPU for paper_sim,
  12 s for a street of ten walkers, 64 s for a generated 51 s crowd run.
)";

// Path length and the planner's figures.
constexpr const char* kPlannerRules = R"(- path_length_m: robot path length from first motion to the goal (or end).
- planner_solve_ms_p50/p99: over PLAN messages with a solve (iterations > 0).
- planner_cycle_ms_p99: over every PLAN's solve_time_us (PLAN carries the
  solver's time, not the whole cycle's; cycles without a solve count as
  what they spent; in a lockstep run it is the compute time modelled).
- solver_failures: PLAN messages with status FALLBACK, STOPPING or RECOVERING
  (no plan met every constraint).
)";

}  // namespace

const char* metrics_rules() {
  static const std::string rules = std::string(kOutcomeRules) + kWindowRules + kReactionRules + kPlannerRules;
  return rules.c_str();
}

MetricsParams MetricsParams::from_config(const config::Node& s) { return config::load<MetricsParams>(s); }

namespace {

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  double pos = q * (v.size() - 1);
  size_t lo = static_cast<size_t>(std::floor(pos));
  size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

bool in_local_map(const Vec2& robot, const Vec2& p, double side) {
  return std::fabs(p.x - robot.x) <= 0.5 * side && std::fabs(p.y - robot.y) <= 0.5 * side;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string opt(const std::optional<double>& v) { return v ? num(*v) : "null"; }

struct Decoded {
  std::vector<evade::sim_truth_t> truth;  // by utime
  std::vector<evade::plan_t> plans;       // in log order
};

Decoded decode_log(const std::vector<bus::LogEvent>& events, RunMetrics* m) {
  Decoded d;
  for (const auto& e : events) {
    if (e.channel == "SIM_TRUTH") {
      evade::sim_truth_t t;
      if (bus::decode(e.data.data(), e.data.size(), &t)) d.truth.push_back(std::move(t));
    } else if (e.channel == "PLAN") {
      evade::plan_t p;
      if (bus::decode(e.data.data(), e.data.size(), &p)) d.plans.push_back(std::move(p));
    } else if (e.channel == "ROUTE" && m->route.empty()) {
      evade::path_t r;
      if (bus::decode(e.data.data(), e.data.size(), &r))
        for (int i = 0; i < r.n; ++i) m->route.push_back({r.x[i], r.y[i]});
    }
  }
  if (d.truth.empty()) throw std::runtime_error("no SIM_TRUTH in the log: metrics need a simulated run");
  std::stable_sort(d.truth.begin(), d.truth.end(), [](const auto& a, const auto& b) { return a.utime < b.utime; });
  return d;
}

// The obstacles by id (in order of first appearance), and which are dynamic.
std::map<int, size_t> collect_obstacles(const std::vector<evade::sim_truth_t>& truth, const MetricsParams& params,
                                        RunMetrics* m) {
  std::map<int, size_t> index;
  for (const auto& t : truth)
    for (const auto& o : t.obstacles) {
      if (!index.count(o.id)) {
        index[o.id] = m->obstacles.size();
        ObstacleTrack tr;
        tr.id = o.id;
        tr.shape = o.shape;
        tr.radius = o.radius;
        tr.length = o.length;
        tr.width = o.width;
        m->obstacles.push_back(tr);
      }
      if (std::hypot(o.vx, o.vy) > params.dynamic_speed_threshold_mps) m->obstacles[index[o.id]].dynamic = true;
    }
  return index;
}

// The smallest clearance of one sample so far (min_dist_m and the closest pair).
void update_closest(const evade::sim_truth_t& t, int k, RunMetrics* m) {
  const OrientedRect robot = footprint(t);
  for (const auto& o : t.obstacles) {
    const double c = obstacle_clearance(robot, o);
    if (c >= m->min_dist_m) continue;
    m->min_dist_m = c;
    m->closest_sample = k;
    m->closest_obstacle = o.id;
    obstacle_closest_points(robot, o, &m->closest_on_robot, &m->closest_on_obstacle);
  }
}

// Marks obstacles entering the local map; true when a moving dynamic one is in it.
bool dynamic_in_map(const evade::sim_truth_t& t, double t_s, const std::map<int, size_t>& index,
                    const MetricsParams& params, RunMetrics* m) {
  bool near = false;
  for (const auto& o : t.obstacles) {
    auto& tr = m->obstacles[index.at(o.id)];
    const bool moving = t.obstacles_moving && std::hypot(o.vx, o.vy) > params.dynamic_speed_threshold_mps;
    if (tr.dynamic && moving && in_local_map({t.x, t.y}, {o.x, o.y}, params.local_map_size_m)) {
      near = true;
      if (!tr.t_enter_s) tr.t_enter_s = t_s;
      tr.t_leave_s = t_s;
    }
  }
  return near;
}

double distance(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

std::optional<double> variance(const std::vector<double>& v) {
  if (v.empty()) return std::nullopt;
  double mean = 0;
  for (double x : v) mean += x;
  mean /= v.size();
  double var = 0;
  for (double x : v) var += (x - mean) * (x - mean);
  return var / v.size();
}

// Everything SIM_TRUTH gives: the path, clearances, contacts, the goal.
void truth_metrics(const std::vector<evade::sim_truth_t>& truth, const MetricsParams& params, RunMetrics* m) {
  const auto index = collect_obstacles(truth, params, m);
  const int64_t t0 = truth.front().utime;
  int64_t t_motion = -1, t_goal = -1;
  m->min_dist_m = std::numeric_limits<double>::infinity();
  ContactTracker contacts(params.fault_approach_speed_mps);
  std::vector<double> speeds_near;
  for (size_t k = 0; k < truth.size(); ++k) {
    const auto& t = truth[k];
    const Vec2 p{t.x, t.y};
    const double t_s = (t.utime - t0) * 1e-6;
    const bool before_goal = t_goal < 0;
    if (before_goal && t_motion < 0 && std::fabs(t.v) > params.motion_threshold_mps) t_motion = t.utime;
    if (before_goal && t_motion >= 0 && k > 0) m->path_length_m += distance(p, m->robot_path.back());
    m->robot_path.push_back(p);
    m->robot_yaw.push_back(t.yaw);
    m->robot_speed.push_back(t.v);
    m->robot_t_s.push_back(t_s);
    for (const auto& o : t.obstacles) {
      auto& tr = m->obstacles[index.at(o.id)];
      tr.path.push_back({o.x, o.y});
      tr.yaw.push_back(o.yaw);
    }
    if (!before_goal) continue;  // after the goal only the picture needs samples
    update_closest(t, static_cast<int>(k), m);
    contacts.add(t, t_s);
    if (dynamic_in_map(t, t_s, index, params, m) && t_motion >= 0) speeds_near.push_back(t.v);
    if (distance(p, m->goal) <= m->goal_tolerance) t_goal = t.utime;
  }
  m->collided = m->min_dist_m <= 0.0;
  m->reached_goal = t_goal >= 0;
  if (m->reached_goal && t_motion >= 0) m->time_to_goal_s = (t_goal - t_motion) * 1e-6;
  m->timed_out = !m->reached_goal || (t_goal - t0) * 1e-6 > m->scenario_duration_s;
  m->final_goal_distance_m = std::hypot(truth.back().x - m->goal.x, truth.back().y - m->goal.y);
  m->speed_var = variance(speeds_near);
  m->contacts = contacts.contacts();
  for (const auto& c : m->contacts) ++(c.at_fault ? m->collisions_at_fault : m->collisions_not_at_fault);
  m->at_fault = m->collisions_at_fault > 0;
  m->success = m->reached_goal && !m->timed_out && !m->at_fault;
}

void planner_stats(const std::vector<evade::plan_t>& plans, RunMetrics* m) {
  std::vector<double> solve_ms, cycle_ms;
  for (const auto& p : plans) {
    ++m->plans;
    if (m->mode.empty()) m->mode = p.mode;
    cycle_ms.push_back(p.solve_time_us * 1e-3);
    if (p.iterations > 0) solve_ms.push_back(p.solve_time_us * 1e-3);
    if (p.status == evade::plan_t::STATUS_FALLBACK || p.status == evade::plan_t::STATUS_STOPPING ||
        p.status == evade::plan_t::STATUS_RECOVERING)
      ++m->solver_failures;
  }
  if (!solve_ms.empty()) {
    m->planner_solve_ms_p50 = percentile(solve_ms, 0.5);
    m->planner_solve_ms_p99 = percentile(solve_ms, 0.99);
  }
  if (!cycle_ms.empty()) m->planner_cycle_ms_p99 = percentile(cycle_ms, 0.99);
}

// The counterfactual replay (metrics_rules()): reaction_time_s, reaction_missed.
void reaction_metrics(const std::vector<bus::LogEvent>& events, const Decoded& d, const MetricsParams& params,
                      planning::PlannerParams planner, RunMetrics* m) {
  try {
    planner.mode = planning::parse_mode(m->mode);
  } catch (const std::exception&) {
    throw std::runtime_error("PLAN.mode \"" + m->mode + "\" is not a planner mode of this build");
  }
  const auto owners = associate_tracks(events, d.truth, params.react_match_radius_m, params.react_owner_switch_s);
  const int64_t t0 = d.truth.front().utime;
  std::vector<ObstacleReaction> reactions;
  for (const auto& tr : m->obstacles) {
    if (!tr.dynamic || !tr.t_enter_s) continue;
    ObstacleReaction r;
    r.obstacle_id = tr.id;
    r.t_enter_utime = t0 + std::llround(*tr.t_enter_s * 1e6);
    r.t_until_utime = t0 + std::llround(std::min(*tr.t_leave_s, *tr.t_enter_s + params.react_max_s) * 1e6);
    r.tracks = owners.tracks_of(tr.id);
    reactions.push_back(r);
  }
  m->replay_check =
      counterfactual_reactions(PlanReplay(planner, events), d.plans, owners, params.react_plan_diff_m, &reactions);
  double sum = 0;
  int n = 0;
  for (const auto& r : reactions) {
    auto& tr =
        *std::find_if(m->obstacles.begin(), m->obstacles.end(), [&](const auto& o) { return o.id == r.obstacle_id; });
    tr.tracks.assign(r.tracks.begin(), r.tracks.end());
    if (r.t_change_utime) tr.t_change_s = (*r.t_change_utime - t0) * 1e-6;
    if (!r.t_react_utime) {
      ++m->reaction_missed;
      continue;
    }
    tr.t_react_s = (*r.t_react_utime - t0) * 1e-6;
    sum += *tr.t_react_s - *tr.t_enter_s;
    ++n;
  }
  if (n > 0) m->reaction_time_s = sum / n;
}

}  // namespace

RunMetrics compute_metrics(const std::vector<bus::LogEvent>& events, const MetricsParams& params,
                           const planning::PlannerParams* planner) {
  RunMetrics m;
  const Decoded d = decode_log(events, &m);
  const auto& first = d.truth.front();
  m.scenario = first.scenario;
  m.goal = {first.goal_x, first.goal_y};
  m.goal_tolerance = first.goal_tolerance;
  m.footprint_length = first.footprint_length;
  m.footprint_width = first.footprint_width;
  m.scenario_duration_s = first.duration_s;
  m.duration_s = (d.truth.back().utime - first.utime) * 1e-6;
  truth_metrics(d.truth, params, &m);
  planner_stats(d.plans, &m);
  if (planner && !d.plans.empty()) reaction_metrics(events, d, params, *planner, &m);
  return m;
}

namespace {

std::string boolean(bool b) { return b ? "true" : "false"; }

std::string contacts_json(const std::vector<Contact>& contacts) {
  if (contacts.empty()) return "[]";
  std::string s = "[\n";
  for (size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    s += "    {\"obstacle_id\": " + std::to_string(c.obstacle_id) + ", \"t_start_s\": " + num(c.t_start_s) +
         ", \"t_end_s\": " + num(c.t_end_s) + ", \"max_penetration_m\": " + num(c.max_penetration_m) +
         ", \"robot_speed_mps\": " + num(c.robot_speed_mps) + ", \"approach_speed_mps\": " + num(c.approach_speed_mps) +
         ", \"at_fault\": " + boolean(c.at_fault) + "}" + (i + 1 < contacts.size() ? ",\n" : "\n");
  }
  return s + "  ]";
}

std::string reactions_json(const std::vector<ObstacleTrack>& obstacles) {
  std::string s;
  for (const auto& o : obstacles) {
    if (!o.dynamic || !o.t_enter_s) continue;
    std::string tracks;
    for (int64_t t : o.tracks) tracks += (tracks.empty() ? "" : ", ") + std::to_string(t);
    s += std::string(s.empty() ? "[\n" : ",\n") + "    {\"obstacle_id\": " + std::to_string(o.id) +
         ", \"t_enter_s\": " + num(*o.t_enter_s) + ", \"t_leave_s\": " + opt(o.t_leave_s) +
         ", \"t_change_s\": " + opt(o.t_change_s) + ", \"t_react_s\": " + opt(o.t_react_s) +
         ", \"reaction_s\": " + (o.t_react_s ? num(*o.t_react_s - *o.t_enter_s) : "null") + ", \"tracks\": [" + tracks +
         "]}";
  }
  return s.empty() ? "[]" : s + "\n  ]";
}

}  // namespace

std::string metrics_json(const RunMetrics& m) {
  std::string s = "{\n";
  auto add = [&](const std::string& k, const std::string& v, bool last = false) {
    s += "  \"" + k + "\": " + v + (last ? "\n" : ",\n");
  };
  add("scenario", "\"" + m.scenario + "\"");
  add("mode", "\"" + m.mode + "\"");
  add("reached_goal", boolean(m.reached_goal));
  add("collided", boolean(m.collided));
  add("at_fault", boolean(m.at_fault));
  add("success", boolean(m.success));
  add("timed_out", boolean(m.timed_out));
  add("collisions_at_fault", std::to_string(m.collisions_at_fault));
  add("collisions_not_at_fault", std::to_string(m.collisions_not_at_fault));
  add("contacts", contacts_json(m.contacts));
  add("min_dist_m", std::isfinite(m.min_dist_m) ? num(m.min_dist_m) : "null");
  add("time_to_goal_s", opt(m.time_to_goal_s));
  add("reaction_time_s", opt(m.reaction_time_s));
  const bool reactions = m.replay_check.has_value();  // computed (see compute_metrics)
  add("reaction_missed", reactions ? std::to_string(m.reaction_missed) : "null");
  add("reactions", reactions ? reactions_json(m.obstacles) : "null");
  if (m.replay_check) {
    add("replay_plans_compared", std::to_string(m.replay_check->compared));
    add("replay_plans_differing", std::to_string(m.replay_check->differing));
    add("replay_max_plan_diff_m", num(m.replay_check->max_distance_m));
  }
  add("speed_var", opt(m.speed_var));
  add("path_length_m", num(m.path_length_m));
  add("planner_solve_ms_p50", opt(m.planner_solve_ms_p50));
  add("planner_solve_ms_p99", opt(m.planner_solve_ms_p99));
  add("planner_cycle_ms_p99", opt(m.planner_cycle_ms_p99));
  add("solver_failures", std::to_string(m.solver_failures));
  add("plans", std::to_string(m.plans));
  add("final_goal_distance_m", num(m.final_goal_distance_m));
  add("duration_s", num(m.duration_s), true);
  return s + "}\n";
}

}  // namespace evade::metrics
