// The planner process core: an MPC cycle on each new list of the mode's
// obstacle input (OBSTACLE_PREDICTIONS, or OBSTACLES in the modes that read
// them), from the newest odometry; when that input is late, ODOMETRY runs a
// cycle once none has run for 1 / rate_hz of bus time. It publishes PLAN
// (naming the prediction list it used) and CMD_VEL, never NaN. Its mode (modes.h) says
// which obstacle input (OBSTACLES or OBSTACLE_PREDICTIONS) enters which
// constraint; in the paper's modes the route is the reference and a failed
// solve brakes, in `evade` the reference goes round what stands on the route
// and a failed solve is recovered from (restarts, relaxed problem, escape,
// the plan with the most clearance; README).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus/core.h"
#include "evade/hidden_region_list_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/obstacles.h"
#include "planning/outcome.h"
#include "planning/params.h"
#include "planning/recent_max.h"
#include "planning/recovery_rank.h"
#include "planning/reference.h"
#include "planning/static_structure.h"
#include "planning/topology_planner.h"

namespace evade::planning {

// How far (m, along each axis) the centre of a footprint disc can get from
// the robot over the horizon: N dt times the larger speed limit (Euler
// steps of the rollout, problem.h) plus the farthest disc's offset, and
// 0.05 m for rounding. The static field's window holds this square round
// the robot (planner_static.cpp).
double static_field_reach_m(const PlannerParams& p);

class PlannerCore : public bus::Core {
 public:
  explicit PlannerCore(PlannerParams params);
  // The core of the whole configuration (PlannerParams::from_config); a
  // non-empty `mode` (modes.h name) replaces planner.mode. Throws
  // ConfigError (file:line: key) or std::invalid_argument (unknown mode).
  static std::unique_ptr<PlannerCore> from_config(const config::Node& root, const std::string& mode = "");

  // The inputs of which only the newest waiting message matters: after a
  // long solve, planning from each queued pose would plan from the past
  // (and judge it stale). The live process and the lockstep loop conflate
  // these.
  static std::vector<std::string> conflated_inputs() {
    return {"ODOMETRY", "OBSTACLES", "OBSTACLE_PREDICTIONS", "ROUTE", "OCCLUSIONS", "ELEVATION_MAP"};
  }

  // Exposed for tests: the last plan published.
  const std::optional<evade::plan_t>& last_plan() const { return last_plan_; }

  // What PLAN.solve_time_us reports for a cycle, from its Ceres iterations
  // and the steady-clock time it took. Default: the measured time. The
  // lockstep closed loop puts its compute model here, so that a log made
  // in simulated time holds the time it charged and is byte-reproducible.
  using SolveTimeModel = std::function<double(int iterations, double measured_us)>;
  void set_solve_time_model(SolveTimeModel model) { solve_time_model_ = std::move(model); }

 private:
  void on_odometry(const evade::odometry_t& odom);
  // A new list of the mode's obstacle input has been accepted: a cycle from
  // the newest odometry, unless there is none fresh enough (the watchdog's)
  // or none newer than the last cycle's (then at the next one).
  void on_new_obstacle_input();
  void plan_cycle(const evade::odometry_t& odom);
  // The cycles that need no solve: stale odometry or obstacle input, no
  // route, at the goal, an invalid track near; publishes their plan and
  // returns true.
  bool published_without_solving(const evade::odometry_t& odom, double v0, double w0);
  // This cycle's problem from the odometry: limits, reference, obstacles.
  Problem make_problem(const evade::odometry_t& odom, double v0, double w0);
  // The previous plan shifted by the steps since it (else holding v0,
  // straight on) and its multipliers mapped by track id.
  void warm_start(const Problem& pb, const evade::odometry_t& odom, double v0, std::vector<double>* warm_u,
                  std::vector<double>* warm_lambda) const;
  // The paper's modes after a failed solve (planner.paper_fallback): the
  // last solved plan shifted, else braking; sets *u, returns the status.
  int8_t paper_fallback(const Problem& pb, const evade::odometry_t& odom, double v0, double w0, std::vector<double>* u);
  // The reference of this cycle: along the route, or round the settled
  // obstacles standing on it (detour.h).
  void make_reference(const evade::odometry_t& odom, Problem* pb);
  // evade's shaping of the reference (ModeSpec::evade_layers): round the
  // settled obstacles and the swept movers; false when the route stands.
  bool detour_reference(const evade::odometry_t& odom, Problem* pb);
  // A mover ahead that the detour grid keeps clear of, as its ellipse swept
  // along its velocity (*swept): a slow leader (going the route's way within
  // detour.leader_max_angle_rad, slower than leader_max_speed_mps: swept
  // leader_sweep_s) or an oncoming one (within oncoming_max_angle_rad of
  // the route's reverse heading, its way passing the robot (passes_robot):
  // swept up to the robot, at most oncoming_sweep_s). Says which it is
  // (kNone: not swept, *swept untouched).
  enum class Sweep { kNone, kLeader, kOncoming };
  Sweep swept_in_grid(const evade::track_prediction_t& t, const evade::odometry_t& odom, Ellipse* swept) const;
  // Whether track t goes towards the robot and its line of motion passes
  // the robot nearer than its larger semi-axis + d_safe_m + the
  // footprint's disc radius + detour.comfort_m: a walker in a lane beside
  // the robot's does not come to it, and sweeping its lane walls the
  // robot off the route (crowd 280: the reference flipped between the way
  // round such lanes and the route, and the robot turned on the spot).
  bool passes_robot(const evade::track_prediction_t& t, const evade::odometry_t& odom) const;
  // A plan the recovery chain tried, with the HEALTH counter naming its kind
  // (mc_hard, mc_dash, ...) that most_clearance adds when it sends it.
  struct Attempt {
    std::vector<double> u;
    const char* label;
  };
  void watchdog();
  // A solver for the next solve of this cycle: what is left of
  // max_cycle_iterations after `spent`, less `reserve`, at most one solve's
  // budget; none (counted) when nothing is left.
  std::optional<CeresMpcSolver> budgeted_solver(int spent, int reserve = 0);
  // With solver.split_budget, the cycle's budget split before solving
  // (mode evade): when a failed hard solve of pb is followed by a recovery
  // solve (the relaxed problem of `chain` when there is something to relax;
  // `own_motion`'s fallback always), that solve's share (recovery_share) is
  // kept from the hard solve and the swerve restarts; else 0.
  int recovery_reserve(const Problem& pb) const;
  // What the restarts leave the recovery solve: with split_budget half of
  // max_cycle_iterations, at most one solve's (max_total_iterations);
  // without, one solve's.
  int recovery_share() const;
  // ---- recovery (planner_recovery.cpp), mode evade ----
  // After the hard solve failed (*res): the strategy of solver.fallback.
  // Each sets *u and *res, adds to *iterations and returns the status.
  int8_t recover(const Problem& pb, const std::vector<double>& warm_u, const evade::odometry_t& odom, double v0,
                 double w0, SolveResult* res, std::vector<double>* u, int* iterations);
  // `chain`: swerve restarts, the relaxed problem and its escape turn, else
  // the candidate plan with the most clearance.
  int8_t recover_chain(const Problem& pb, const std::vector<double>& warm_u, const evade::odometry_t& odom, double v0,
                       double w0, SolveResult* res, std::vector<double>* u, int* iterations);
  // `own_motion`: swerve restarts, else the one fallback (fallback.h): its
  // relaxed problem's plan (RECOVERING), else braking (STOPPING).
  int8_t recover_own_motion(const Problem& pb, const std::vector<double>& warm_u, double v0, double w0,
                            SolveResult* res, std::vector<double>* u, int* iterations);
  // Both: braking at the limits projected onto pb's bounds; whether it
  // misses the hard problem (then the restarts are skipped: the relaxed
  // problem decides); the hard problem from a swerve to either side
  // (manoeuvres.h), `reserve` iterations kept for the solve after it, the
  // first feasible one into *res, each finite plan into *tried when given.
  std::vector<double> projected_braking(const Problem& pb, double v0, double w0) const;
  // False when solver.rank_outcome judges the relaxed plan u as meeting a
  // mover's body (plan_outcome): most_clearance decides among the candidates.
  bool relaxed_plan_stands(const Problem& pb, const std::vector<double>& u) const;
  // The passive-safety bounds (passive_safety.h) put into *pb when
  // planner.passive_safety is on and they bind: the speed (HEALTH
  // passive_speed_bound) and, with turn_bound, the first step's turn
  // (HEALTH passive_turn_bound). Whether the speed bound bound.
  bool apply_passive_bounds(Problem* pb);
  // pb so bound: the problem of every plan the recovery sends once the hard
  // problem has failed (with every_plan, pb itself: make_problem bound the
  // cycle's problem, once).
  Problem passively_bounded(const Problem& pb);
  OutcomeMargin outcome_margin() const;  // solver.outcome_margin_*
  bool braking_misses(const Problem& pb, const std::vector<double>& brake) const;
  void swerve_restarts(const Problem& pb, int reserve, SolveResult* res, int* iterations, std::vector<Attempt>* tried);
  // The last feasible plan shifted to this cycle, its tail braking; false
  // when there is none from within the horizon.
  bool last_feasible_shifted(const evade::odometry_t& odom, std::vector<double>* u) const;
  // Nothing met every constraint: of the plans at hand (`attempts`, the
  // last feasible plan shifted, braking) the one with the most clearance.
  int8_t most_clearance(const Problem& pb, const std::vector<Attempt>& attempts, const evade::odometry_t& odom,
                        double v0, double w0, std::vector<double>* u);
  // How most_clearance judges a plan's rollout (with solver.rank_outcome,
  // plan_outcome over 2N steps).
  RecoveryJudgement judge_recovery_plan(const Problem& pb, const std::vector<double>& states) const;
  // passive_safety.slow_chosen: u, the recovery's chosen plan (judged
  // `judged`), slowed onto the reach bounds (project_onto_reach), unless
  // the slowed plan goes into structure where u did not, deeper into it,
  // or is worse against the movers as passive_safety.slowed_refused_if
  // says (slowed_is_worse). Returns whether it slowed u.
  bool slow_onto_reach(const Problem& pb, const RecoveryJudgement& judged, std::vector<double>* u) const;
  // Braking at the deceleration limits from (v, omega), as plan controls.
  std::vector<double> braking_controls(double v, double omega) const;
  // PlannerParams::escape_*: when *u (a relaxed plan) makes no headway from
  // inside d_safe, replaces it with a turn on the spot towards the way out
  // and returns true.
  bool escape_turn(const Problem& pb, double v0, double omega0, std::vector<double>* u) const;
  // Mode evade with planner.guidance.enabled: the cycle's solves and choice
  // by TopologyPlanner (planner_guidance.cpp), then as plan_cycle's end.
  void plan_with_guidance(const Problem& pb, const std::vector<double>& warm_u, const std::vector<double>& warm_lambda,
                          const evade::odometry_t& odom, double v0, double w0);
  // The end of a cycle: remembers the plan for the next warm start (and a
  // feasible one for the fallback) and publishes it.
  void finish_cycle(const evade::odometry_t& odom, int8_t status, const Problem& pb, const std::vector<double>& u,
                    const SolveResult& res, double solve_us, int iterations);
  // The PLAN message of controls u and their rollout's states.
  evade::plan_t plan_message(const evade::odometry_t& odom, int8_t status, const Problem& pb,
                             const std::vector<double>& u, const std::vector<double>& states, double solve_us,
                             int iterations) const;
  void publish_plan(const evade::odometry_t& odom, int8_t status, const Problem* pb, const std::vector<double>& u,
                    double solve_us, int iterations, int num_obstacles);
  // CMD_VEL's speed for controls u: the first step's, or with brake_ahead
  // in mode evade the second step's where that step brakes at the
  // deceleration limit (same direction).
  double commanded_speed(const std::vector<double>& u) const;

  // ---- static structure (planner_static.cpp, static_structure.h) ----
  // Mode evade with static_field.enabled: ELEVATION_MAP is kept (the last
  // few, gated like the predictions).
  void subscribe_static_map();
  // This cycle's field (static_.update), counted (static_field, or
  // static_map_stale / static_map_invalid: every track by its ellipse);
  // sets the detour grid's field.
  void update_static_field(const evade::odometry_t& odom);
  // BLOCKED beside structure: a plan of v = 0 that the field's constraint
  // holds against a wall (active at some step) is a local minimum for a
  // robot that cannot reverse. When blocked and *u makes no headway (it
  // ends within escape.min_progress_m of the start, or it is still within
  // that halfway through the horizon where the footprint moved straight
  // on by min_progress_m would be in the margin), replaces it with a
  // turn on the spot (braking, at the limits; escape.h) to the way out of
  // the structure: the heading to the reference's end brought within
  // escape.cone_half_angle of grad h of the field, turned only as far as
  // it can still stop short of the structure's margin. The short way round, or the long way when the
  // short one does not do: the turn must meet the movers' constraints and
  // the rate limits, enter the structure's margin by at most 0.01 m, and
  // turn. It goes on in the next cycles (first the way round it took)
  // until the robot faces the way out or a plan makes headway. True when
  // *u was replaced.
  bool escape_from_structure(const Problem& pb, const evade::odometry_t& odom, bool is_blocked, std::vector<double>* u);
  int escape_side_ = 0;  // the way round of the last cycle's such turn (+1 left, -1 right; 0 none)
  StaticStructure static_;

  PlannerParams p_;
  const ModeSpec& mode_;
  RouteFollower route_;
  DetourPlanner detour_;
  SettledMemory settled_;
  CurveFitHistory history_;
  TopologyPlanner topology_;
  // What the planner has seen of a track id: its first prediction list, and
  // where its centre (step 0) has stayed within solver.still_radius_m since,
  // and the fastest its tracker has reported it over the last
  // passive_safety.speed_memory_s.
  struct Sighting {
    int64_t first_utime = 0;
    double still_x = 0, still_y = 0;
    int64_t still_since_utime = 0;
    RecentMax speed;
  };
  std::map<int64_t, Sighting> seen_;  // track id -> its sighting (ids gone are forgotten)
  void record_sightings(const evade::prediction_list_t& m);
  double track_age_s(int64_t id, int64_t utime) const;    // since its first prediction (0 for an unknown id)
  double track_still_s(int64_t id, int64_t utime) const;  // since its centre last moved (0 for an unknown id)
  double track_recent_speed(int64_t id) const;            // its fastest lately (m/s, 0 for an unknown id)
  std::optional<evade::prediction_list_t> predictions_;
  int64_t predictions_rx_ = -1;                            // bus time the predictions arrived
  std::optional<evade::obstacle_list_t> observed_;         // the last OBSTACLES
  std::optional<evade::hidden_region_list_t> occlusions_;  // the last OCCLUSIONS (mode evade: occlusion_speed.h)
  int64_t observed_rx_ = -1;                               // bus time they arrived
  int64_t odometry_rx_ = -1;                               // bus time of the last odometry
  std::optional<evade::odometry_t> last_odometry_;
  int64_t last_cycle_now_ = -1;       // bus time of the last planning cycle (the odometry fallback's clock)
  int64_t last_cycle_odometry_ = -1;  // utime of the odometry the last cycle planned from
  bool cycle_pending_ = false;        // a list came with no newer odometry than that: the next one plans
  int64_t period_us_;
  // warm start: previous solution (any status) and previous feasible plan
  std::vector<double> prev_u_;
  int64_t prev_utime_ = -1;
  std::vector<double> prev_multipliers_;
  double prev_penalty_ = 0;
  std::vector<int64_t> prev_ids_;
  std::vector<double> feasible_u_;
  int64_t feasible_utime_ = -1;
  std::optional<evade::plan_t> last_plan_;
  // PLAN.status BLOCKED: the route progress last reached blocked_progress_m
  // beyond the mark, and the odometry utime then
  double progress_mark_m_ = 0.0;
  int64_t progress_mark_utime_ = -1;
  // Moves the mark on (or restarts it: no route, at the goal, a new route);
  // true when the robot has made no progress for blocked_after_s.
  bool blocked(const evade::odometry_t& odom, bool restart);
  bool predictions_stale() const;  // no predictions (when required) or older than predictions_max_age_s
  bool observed_stale() const;     // no OBSTACLES (when required) or older than obstacles_max_age_s
  bool input_stale() const;        // the mode's obstacle input (ModeSpec::source) is stale
  // ---- input gate (planner_inputs.cpp, issue 20) ----
  // False when this odometry must not be used: late, from the future, not
  // newer than the last, or the first of a new epoch (then start_new_epoch
  // has stopped the robot and dropped every state of the old frame).
  bool accept_odometry(const evade::odometry_t& odom);
  void start_new_epoch(const evade::odometry_t& odom);
  // False for predictions (or OBSTACLES) late, from the future, or older
  // than the epoch.
  bool accept_predictions(const evade::prediction_list_t& m);
  bool accept_observed(const evade::obstacle_list_t& m);
  // A message of `input` stamped utime: false (counted `<input>_late`,
  // `<input>_future`) unless within max_age_s of now either way; false
  // (`<input>_before_epoch`) when stamped before the current epoch began.
  bool on_time(const std::string& input, int64_t utime, double max_age_s);
  bool of_this_epoch(const std::string& input, int64_t utime);
  // A track (or observed ellipse, in the modes that read OBSTACLES) that
  // cannot be constrained against near the robot: publishes a braking plan
  // (STATUS_STOPPING) and returns true.
  bool brake_for_invalid_track(const evade::odometry_t& odom, double v0, double w0);
  bool have_epoch_ = false;
  int64_t epoch_ = 0;
  int64_t epoch_start_utime_ = -1;  // first odometry of the current epoch, once it changed
  double last_cmd_v_ = 0, last_cmd_omega_ = 0;
  int64_t last_cmd_now_ = -1;
  SolveTimeModel solve_time_model_;
};

}  // namespace evade::planning
