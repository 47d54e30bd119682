#include "closedloop/closed_loop.h"

#include <stdexcept>

#include "base/base_driver_core.h"
#include "bus/auth.h"
#include "closedloop/cpu.h"
#include "closedloop/event_queue.h"
#include "closedloop/lockstep_params.h"
#include "closedloop/process_node.h"
#include "closedloop/run_monitor.h"
#include "closedloop/serial_line.h"
#include "evade/plan_t.hpp"
#include "mapping/elevation_map_core.h"
#include "planning/planner_core.h"
#include "prediction/predictor_core.h"
#include "route/route_publisher.h"
#include "sensing/lidar_driver_core.h"
#include "sim/sim_core.h"
#include "tracking/tracker_core.h"

namespace evade::closedloop {

namespace {

int64_t us(double s) { return std::llround(s * 1e6); }

bool published_other_than_health(const std::vector<bus::LogEvent>& outputs) {
  for (const auto& o : outputs)
    if (o.channel != bus::kHealthChannel) return true;
  return false;
}

// The PLAN a callback published, if any.
bool plan_of(const std::vector<bus::LogEvent>& out, evade::plan_t* plan) {
  for (const auto& o : out)
    if (o.channel == "PLAN" && bus::decode(o.data.data(), o.data.size(), plan)) return true;
  return false;
}

// callback_s per callback, publish_s more when it published.
ProcessNode::ComputeModel fixed_cost(const ProcessCost& c) {
  return [c](const std::vector<bus::LogEvent>& out) {
    return us(c.callback_s + (published_other_than_health(out) ? c.publish_s : 0.0));
  };
}

// A planner cycle is charged the solve time its PLAN reports (the compute
// model put in PLAN.solve_time_us, see PlannerCore::set_solve_time_model),
// plus callback_s; other callbacks as fixed_cost.
ProcessNode::ComputeModel planner_cost(const ProcessCost& c) {
  return [c, other = fixed_cost(c)](const std::vector<bus::LogEvent>& out) {
    evade::plan_t plan;
    if (plan_of(out, &plan)) return us(c.callback_s) + std::max<int64_t>(0, plan.solve_time_us);
    return other(out);
  };
}

}  // namespace

struct ClosedLoop::Impl {
  LockstepParams params;
  LockstepRun run;
  EventQueue q;
  std::unique_ptr<sim::SimCore> sim;
  std::unique_ptr<sensing::LidarDriverCore> lidar;
  std::unique_ptr<base::BaseDriverCore> base;
  std::unique_ptr<planning::PlannerCore> planner;
  std::vector<std::unique_ptr<bus::Core>> others;  // elevation_map, tracker, predictor, route
  std::unique_ptr<RunMonitor> monitor;
  std::vector<std::unique_ptr<bus::HmacAuth>> auths;  // one per robot process, as live
  std::vector<std::unique_ptr<ProcessNode>> nodes;
  std::map<std::string, std::vector<ProcessNode*>> subscribers;
  std::unique_ptr<Cpu> cpu;  // the shared cores (none: each process has its own)
  std::map<std::string, ProcessStats> profiles;
  std::unique_ptr<SerialLine> to_base, to_sim;
  // What the simulator's running callback made; it leaves when the
  // callback has had its compute time, as any process's output.
  std::vector<Bytes> sim_packets;
  std::vector<uint8_t> sim_serial;
  ProcessNode* sim_node = nullptr;
  ProcessNode* lidar_node = nullptr;
  ProcessNode* base_node = nullptr;
  bus::LogWriter* log = nullptr;
  double duration_s = 0.0;

  void build(const config::Node& root, sim::Scenario scenario);
  ProcessNode* add(bus::Core& core, ProcessNode::ComputeModel model, std::set<std::string> conflated = {});
  void route(const std::string& channel, int64_t t_leave, const Bytes& data);
  void wire_devices(int baud_rate);
  void profile(const bus::Core& core, const std::vector<bus::LogEvent>& out, double cpu_s);
};

// One profiled callback, filed by its size (CpuSample).
void ClosedLoop::Impl::profile(const bus::Core& core, const std::vector<bus::LogEvent>& out, double cpu_s) {
  ProcessStats& p = profiles[core.name()];
  evade::plan_t plan;
  if (&core == sim.get())
    p.samples.push_back({static_cast<double>(sim_packets.size()), cpu_s});
  else if (&core == planner.get() && plan_of(out, &plan))
    p.plan_samples.push_back({static_cast<double>(plan.iterations), cpu_s});
  else
    p.samples.push_back({published_other_than_health(out) ? 1.0 : 0.0, cpu_s});
}

ProcessNode* ClosedLoop::Impl::add(bus::Core& core, ProcessNode::ComputeModel model, std::set<std::string> conflated) {
  const bool charged = static_cast<bool>(model);  // the run monitor is not a process of the robot
  nodes.push_back(std::make_unique<ProcessNode>(core, q, std::move(model), std::move(conflated)));
  ProcessNode* n = nodes.back().get();
  n->set_router([this](const std::string& ch, int64_t t, const Bytes& data) { route(ch, t, data); });
  n->set_cpu(cpu.get());
  if (run.cpu_clock && charged)
    n->set_profiler(run.cpu_clock,
                    [this, &core](const std::vector<bus::LogEvent>& out, double cpu_s) { profile(core, out, cpu_s); });
  for (const auto& ch : core.channels()) subscribers[ch].push_back(n);
  return n;
}

// An LCM message: logged (as lcm-logger would record it) and delivered to
// every subscriber when it arrives.
void ClosedLoop::Impl::route(const std::string& channel, int64_t t_leave, const Bytes& data) {
  const int64_t t = t_leave + us(params.bus_latency_s);
  if (log && !run.unlogged.count(channel)) q.at(t, [this, t, channel, data] { log->write(t, channel, *data); });
  auto it = subscribers.find(channel);
  if (it == subscribers.end()) return;
  for (ProcessNode* n : it->second) q.at(t, [n, channel, data] { n->deliver(channel, data); });
}

// The simulator's two devices: LiDAR packets over UDP to the driver (every
// port, as in a capture: the decoder tells data from DIFOP by content), and
// the Scout's UART both ways.
void ClosedLoop::Impl::wire_devices(int baud_rate) {
  const int64_t udp = us(params.udp_latency_s);
  sim->set_packet_sink([this](const sim::Packet& p) {
    sim_packets.push_back(std::make_shared<const std::vector<uint8_t>>(p.begin(), p.end()));
  });
  to_base = std::make_unique<SerialLine>(q, baud_rate, [this](const std::vector<uint8_t>& b) {
    base_node->input([this, b] { base->on_serial_bytes(b.data(), b.size()); }, "serial");
  });
  to_sim = std::make_unique<SerialLine>(q, baud_rate, [this](const std::vector<uint8_t>& b) {
    sim_node->input([this, b] { sim->on_serial_bytes(b.data(), b.size()); }, "");
  });
  sim->set_serial_sink([this](const uint8_t* d, size_t n) { sim_serial.insert(sim_serial.end(), d, d + n); });
  sim_node->set_after([this, udp](int64_t leave) {
    for (const Bytes& bytes : sim_packets)
      q.at(leave + udp, [this, bytes] {
        lidar_node->input([this, bytes] { lidar->on_packet(bytes->data(), bytes->size()); }, "udp");
      });
    sim_packets.clear();
    if (!sim_serial.empty()) to_base->write(leave, std::move(sim_serial));
    sim_serial.clear();
  });
  base_node->set_after([this](int64_t leave) {
    std::vector<uint8_t> tx = base->take_tx();
    if (!tx.empty()) to_sim->write(leave, std::move(tx));
  });
}

void ClosedLoop::Impl::build(const config::Node& root, sim::Scenario scenario) {
  duration_s = scenario.duration_s;
  if (run.seed) scenario.seed = *run.seed;
  sim = sim::SimCore::from_config(root, scenario);
  lidar = sensing::LidarDriverCore::from_config(root, sensing::LidarDriverCore::Source::kPackets);
  base::BaseDriverRun base_run;
  base_run.initial_pose = base::Pose2{scenario.start.x, scenario.start.y, scenario.start.yaw};
  base = base::BaseDriverCore::from_config(root, base_run);
  planner = planning::PlannerCore::from_config(root, run.planner_mode);
  const LockstepParams* lp = &params;
  planner->set_solve_time_model([lp](int it, double measured_us) { return lp->planner_cycle_us(it, measured_us); });
  others.push_back(mapping::ElevationMapCore::from_config(root));
  others.push_back(tracking::TrackerCore::from_config(root));
  others.push_back(prediction::PredictorCore::from_config(root));
  others.push_back(route::RoutePublisher::from_config(root, sim::route_waypoints(scenario), scenario.file));
  RunMonitorParams mp;
  mp.margin_s = params.goal_margin_s;
  mp.quiet = run.quiet;
  monitor = std::make_unique<RunMonitor>(mp);

  // The robot's processes sign and check the authenticated channels with
  // the configured key, as they do live, so a lockstep log replays with it.
  const bus::AuthSetup keys = bus::load_auth(root);
  std::vector<bus::Core*> robot = {base.get(), planner.get()};
  for (auto& c : others) robot.push_back(c.get());
  for (bus::Core* c : robot) {
    auths.push_back(keys.make(c->name()));
    c->set_authenticator(auths.back().get());
  }

  if (params.cpu_cores > 0) cpu = std::make_unique<Cpu>(q, params.cpu_cores, params.background_load_cores);
  const ProcessCost sc = params.costs.at("sim");
  sim_node = add(*sim, [this, sc](const std::vector<bus::LogEvent>&) {
    return us(sc.callback_s + sc.packet_s * static_cast<double>(sim_packets.size()));
  });
  lidar_node = add(*lidar, fixed_cost(params.costs.at("lidar_driver")));
  base_node = add(*base, fixed_cost(params.costs.at("base_driver")));
  for (auto& c : others) add(*c, fixed_cost(params.costs.at(c->name())));
  const auto conflated = planning::PlannerCore::conflated_inputs();
  add(*planner, planner_cost(params.costs.at("planner")), {conflated.begin(), conflated.end()});
  add(*monitor, nullptr);
  wire_devices(base->params().baud_rate);
}

ClosedLoop::ClosedLoop(const config::Node& root, const sim::Scenario& scenario, const LockstepRun& run)
    : impl_(std::make_unique<Impl>()) {
  impl_->params = LockstepParams::from_config(root);
  if (!run.planner_compute.empty()) impl_->params.planner_compute = parse_planner_compute(run.planner_compute);
  if (run.cpu_cores) impl_->params.cpu_cores = *run.cpu_cores;
  if (run.background_load_cores) impl_->params.background_load_cores = *run.background_load_cores;
  impl_->run = run;
  impl_->build(root, scenario);
}

ClosedLoop::~ClosedLoop() = default;

LockstepResult ClosedLoop::run(bus::LogWriter* log) {
  Impl& m = *impl_;
  m.log = log;
  const int64_t t0 = m.params.start_utime_us;
  m.q.set_now(t0);
  m.base_node->input([&m] { m.base->on_link_opened(); }, "");
  for (auto& n : m.nodes) n->start(t0);
  // A safety cap in case the monitor never hears the end (a broken sim).
  const int64_t cap = t0 + us(m.duration_s + 60.0);
  LockstepResult r;
  while (m.monitor->result() == RunMonitor::kRunning && m.q.next_time() <= cap && m.q.run_next()) {
  }
  r.outcome = m.monitor->result();
  r.sim_s = (m.q.now() - t0) * 1e-6;
  r.events = static_cast<int64_t>(m.q.events_run());
  r.cpu_work_s = m.cpu ? m.cpu->work_done_us() * 1e-6 : 0.0;
  for (auto& n : m.nodes) {
    ProcessStats& p = r.processes[n->core().name()];
    p = std::move(m.profiles[n->core().name()]);
    p.callbacks = n->callbacks();
    p.compute_s = n->compute_us() * 1e-6;
  }
  return r;
}

}  // namespace evade::closedloop
