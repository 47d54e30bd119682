#include "planning/guidance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The label change between two consecutive steps (header comment): the
// vector (ds, rho) from the obstacle to the robot crossing ds = 0.
int crossing_label(double ds0, double rho0, double ds1, double rho1) {
  const bool ahead0 = ds0 >= 0.0, ahead1 = ds1 >= 0.0;
  if (ahead0 == ahead1) return 0;
  const double t = ds0 / (ds0 - ds1);  // ds0 != ds1 here
  const double rho = rho0 + t * (rho1 - rho0);
  const int side = rho >= 0.0 ? 1 : -1;
  return ahead1 ? side : -side;
}

// (ds, rho) of point (px, py) relative to obstacle o at step k.
inline void relative(const RouteFrame& f, const ObstacleTrack& o, int k, double px, double py, double* ds,
                     double* rho) {
  const double dx = px - o.x[k], dy = py - o.y[k];
  *ds = f.ex * dx + f.ey * dy;
  *rho = -f.ey * dx + f.ex * dy;
}

// Adds to labels[i] the crossings of positions (xs, ys) at steps k_first..k_last.
void add_labels(const Problem& pb, const RouteFrame& f, int k_first, const double* xs, const double* ys, int count,
                std::vector<int>* labels) {
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    const ObstacleTrack& o = pb.obstacles[i];
    if (o.field) continue;  // static structure is the local solves' (static_field.h)
    double ds0, rho0;
    relative(f, o, k_first, xs[0], ys[0], &ds0, &rho0);
    for (int n = 1; n < count; ++n) {
      double ds1, rho1;
      relative(f, o, k_first + n, xs[n], ys[n], &ds1, &rho1);
      (*labels)[i] += crossing_label(ds0, rho0, ds1, rho1);
      ds0 = ds1;
      rho0 = rho1;
    }
  }
}

// Adds to labels[i] the crossing of the path's continuation from (x, y)
// at step N along the route's axis, obstacle i held where it is at N: on
// its side when it is ahead and the continuation clears its ellipse (its
// larger semi-axis), none when it runs into it.
void add_end_labels(const Problem& pb, const RouteFrame& f, double x, double y, std::vector<int>* labels) {
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    const ObstacleTrack& o = pb.obstacles[i];
    if (o.field) continue;
    double ds, rho;
    relative(f, o, pb.N, x, y, &ds, &rho);
    const double half_width = std::max(o.a[pb.N], o.b[pb.N]);
    if (ds < 0.0 && std::fabs(rho) > half_width) (*labels)[i] += rho > 0.0 ? 1 : -1;
  }
}

Signature make_signature(const Problem& pb, const std::vector<int>& labels) {
  Signature s;
  for (size_t i = 0; i < pb.obstacles.size(); ++i) s.labels.push_back({pb.obstacles[i].id, labels[i]});
  std::sort(s.labels.begin(), s.labels.end());
  return s;
}

// An obstacle's ellipses as the lattice tests them: grown by the
// footprint's reach and d_safe, or by the reach alone when the robot
// starts within d_safe of it (else no way out exists).
struct Blocker {
  std::vector<double> cx, cy, c, s, ia2, ib2, r2;  // per step: centre, orientation, 1/A^2, 1/B^2, bound^2
};

std::vector<Blocker> make_blockers(const Problem& pb) {
  // the footprint as the disc round its discs (the lattice has no heading)
  double reach = 0.0;
  for (double off : pb.footprint.offsets) reach = std::max(reach, std::fabs(off) + pb.footprint.radius);
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  std::vector<Blocker> out;
  for (const ObstacleTrack& o : pb.obstacles) {
    if (o.field) continue;  // the lattice sees ellipses only
    const bool start_inside = barrier_at(pb, o, 0, start).h < 0.0;
    const double grow = reach + (start_inside ? 0.0 : pb.d_safe);
    Blocker b;
    for (int k = 0; k <= pb.N; ++k) {
      const double A = o.a[k] + grow, B = o.b[k] + grow;
      b.cx.push_back(o.x[k]);
      b.cy.push_back(o.y[k]);
      b.c.push_back(std::cos(o.theta[k]));
      b.s.push_back(std::sin(o.theta[k]));
      b.ia2.push_back(1.0 / (A * A));
      b.ib2.push_back(1.0 / (B * B));
      b.r2.push_back(std::max(A, B) * std::max(A, B));
    }
    out.push_back(std::move(b));
  }
  return out;
}

bool blocked(const std::vector<Blocker>& bs, int k, double px, double py) {
  for (const Blocker& b : bs) {
    const double dx = px - b.cx[k], dy = py - b.cy[k];
    if (dx * dx + dy * dy >= b.r2[k]) continue;
    const double u = dx * b.c[k] + dy * b.s[k], v = -dx * b.s[k] + dy * b.c[k];
    if (u * u * b.ia2[k] + v * v * b.ib2[k] < 1.0) return true;
  }
  return false;
}

struct Edge {
  int from, to;  // node indices within their layers
  double cost;
};

// The lattice and its dynamic programming (header comment).
class Lattice {
 public:
  Lattice(const Problem& pb, const GuidanceParams& g);
  std::vector<GuidancePath> classes(int max_classes);

 private:
  void node_xy(int node, double* x, double* y) const;
  bool edge(int j, int from, int to, double* cost) const;  // transition j-1 -> j
  void forward();
  void backward();
  void tree_labels();
  GuidancePath path_through(int j, int node) const;

  const Problem& pb_;
  RouteFrame f_;
  std::vector<Blocker> blockers_;
  std::vector<int> layer_k_;  // MPC step of each layer, layer 0 = step 0
  int ns_ = 0, nd_ = 0, cd_ = 0;
  double ds_ = 0, dd_ = 0;
  std::vector<std::vector<Edge>> edges_;                // per transition j (1..L), index j
  std::vector<std::vector<double>> fwd_, bwd_;          // per layer, per node
  std::vector<std::vector<int>> pred_, succ_;           // per layer, per node (-1 none)
  std::vector<std::vector<std::vector<int>>> lf_, lb_;  // labels of the forward / backward tree path
  int start_ = 0;
};

Lattice::Lattice(const Problem& pb, const GuidanceParams& g)
    : pb_(pb), f_(route_frame(pb)), blockers_(make_blockers(pb)) {
  layer_k_.push_back(0);
  for (int k = g.layer_steps; k < pb.N + g.layer_steps; k += g.layer_steps) layer_k_.push_back(std::min(k, pb.N));
  ds_ = g.longitudinal_step_m;
  dd_ = g.lateral_step_m;
  ns_ = static_cast<int>(std::floor(pb.lim.v_max * pb.N * pb.dt / ds_ + 1e-9)) + 1;
  cd_ = static_cast<int>(std::floor(g.lateral_max_m / dd_ + 1e-9));
  nd_ = 2 * cd_ + 1;
  start_ = cd_;  // s index 0, d index cd_
  forward();
  backward();
  tree_labels();
}

void Lattice::node_xy(int node, double* x, double* y) const {
  const double s = (node / nd_) * ds_, d = (node % nd_ - cd_) * dd_;
  *x = f_.ox + s * f_.ex - d * f_.ey;
  *y = f_.oy + s * f_.ey + d * f_.ex;
}

bool Lattice::edge(int j, int from, int to, double* cost) const {
  const int k0 = layer_k_[j - 1], k1 = layer_k_[j];
  double x0, y0, x1, y1;
  node_xy(from, &x0, &y0);
  node_xy(to, &x1, &y1);
  double c = 0.0;
  for (int k = k0 + 1; k <= k1; ++k) {
    const double t = static_cast<double>(k - k0) / (k1 - k0);
    const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
    if (blocked(blockers_, k, x, y)) return false;
    const double w = k == pb_.N ? pb_.w.p_xy : pb_.w.q_xy;
    c += w * ((x - pb_.ref_x[k]) * (x - pb_.ref_x[k]) + (y - pb_.ref_y[k]) * (y - pb_.ref_y[k]));
  }
  *cost = c;
  return true;
}

void Lattice::forward() {
  const int L = static_cast<int>(layer_k_.size()) - 1, nodes = ns_ * nd_;
  fwd_.assign(L + 1, std::vector<double>(nodes, kInf));
  pred_.assign(L + 1, std::vector<int>(nodes, -1));
  edges_.assign(L + 1, {});
  fwd_[0][start_] = 0.0;
  for (int j = 1; j <= L; ++j) {
    // v_max over the layer's time, plus half a cell's diagonal for the grid
    const double reach = pb_.lim.v_max * (layer_k_[j] - layer_k_[j - 1]) * pb_.dt + 0.5 * std::hypot(ds_, dd_);
    const int max_is = static_cast<int>(std::floor(reach / ds_)), max_id = static_cast<int>(std::floor(reach / dd_));
    for (int from = 0; from < nodes; ++from) {
      if (fwd_[j - 1][from] == kInf) continue;
      const int is0 = from / nd_, id0 = from % nd_;
      for (int a = 0; a <= max_is && is0 + a < ns_; ++a)
        for (int b = -max_id; b <= max_id; ++b) {
          const int id = id0 + b;
          if (id < 0 || id >= nd_ || std::hypot(a * ds_, b * dd_) > reach) continue;
          const int to = (is0 + a) * nd_ + id;
          double c;
          if (!edge(j, from, to, &c)) continue;
          edges_[j].push_back({from, to, c});
          if (fwd_[j - 1][from] + c < fwd_[j][to]) {
            fwd_[j][to] = fwd_[j - 1][from] + c;
            pred_[j][to] = from;
          }
        }
    }
  }
}

void Lattice::backward() {
  const int L = static_cast<int>(layer_k_.size()) - 1, nodes = ns_ * nd_;
  bwd_.assign(L + 1, std::vector<double>(nodes, kInf));
  succ_.assign(L + 1, std::vector<int>(nodes, -1));
  for (int n = 0; n < nodes; ++n)
    if (fwd_[L][n] < kInf) bwd_[L][n] = 0.0;
  for (int j = L; j >= 1; --j)
    for (const Edge& e : edges_[j]) {
      const double c = bwd_[j][e.to] + e.cost;
      if (c < bwd_[j - 1][e.from] || (c == bwd_[j - 1][e.from] && e.to < succ_[j - 1][e.from])) {
        bwd_[j - 1][e.from] = c;
        succ_[j - 1][e.from] = e.to;
      }
    }
}

void Lattice::tree_labels() {
  const int L = static_cast<int>(layer_k_.size()) - 1, nodes = ns_ * nd_, no = static_cast<int>(pb_.obstacles.size());
  lf_.assign(L + 1, std::vector<std::vector<int>>(nodes));
  lb_.assign(L + 1, std::vector<std::vector<int>>(nodes));
  // the labels of the straight edge from node a (layer j - 1) to b (layer j)
  std::vector<double> xs, ys;
  auto edge_labels = [&](int j, int a, int b, std::vector<int>* labels) {
    const int k0 = layer_k_[j - 1], k1 = layer_k_[j];
    double x0, y0, x1, y1;
    node_xy(a, &x0, &y0);
    node_xy(b, &x1, &y1);
    xs.resize(k1 - k0 + 1);
    ys.resize(k1 - k0 + 1);
    for (int k = k0; k <= k1; ++k) {
      const double t = static_cast<double>(k - k0) / (k1 - k0);
      xs[k - k0] = x0 + t * (x1 - x0);
      ys[k - k0] = y0 + t * (y1 - y0);
    }
    add_labels(pb_, f_, k0, xs.data(), ys.data(), k1 - k0 + 1, labels);
  };
  lf_[0][start_].assign(no, 0);
  for (int j = 1; j <= L; ++j)
    for (int n = 0; n < nodes; ++n) {
      if (pred_[j][n] < 0) continue;
      lf_[j][n] = lf_[j - 1][pred_[j][n]];
      edge_labels(j, pred_[j][n], n, &lf_[j][n]);
    }
  for (int n = 0; n < nodes; ++n) {
    if (bwd_[L][n] != 0.0) continue;
    lb_[L][n].assign(no, 0);
    double x, y;
    node_xy(n, &x, &y);
    add_end_labels(pb_, f_, x, y, &lb_[L][n]);
  }
  for (int j = L - 1; j >= 0; --j)
    for (int n = 0; n < nodes; ++n) {
      if (succ_[j][n] < 0) continue;
      lb_[j][n] = lb_[j + 1][succ_[j][n]];
      edge_labels(j + 1, n, succ_[j][n], &lb_[j][n]);
    }
}

GuidancePath Lattice::path_through(int j, int node) const {
  const int L = static_cast<int>(layer_k_.size()) - 1;
  std::vector<int> chain(L + 1);
  chain[j] = node;
  for (int i = j; i > 0; --i) chain[i - 1] = pred_[i][chain[i]];
  for (int i = j; i < L; ++i) chain[i + 1] = succ_[i][chain[i]];
  GuidancePath p;
  p.cost = fwd_[j][node] + bwd_[j][node];
  p.x.resize(pb_.N + 1);
  p.y.resize(pb_.N + 1);
  for (int i = 1; i <= L; ++i) {
    double x0, y0, x1, y1;
    node_xy(chain[i - 1], &x0, &y0);
    node_xy(chain[i], &x1, &y1);
    const int k0 = layer_k_[i - 1], k1 = layer_k_[i];
    for (int k = k0; k <= k1; ++k) {
      const double t = static_cast<double>(k - k0) / (k1 - k0);
      p.x[k] = x0 + t * (x1 - x0);
      p.y[k] = y0 + t * (y1 - y0);
    }
  }
  return p;
}

std::vector<GuidancePath> Lattice::classes(int max_classes) {
  const int L = static_cast<int>(layer_k_.size()) - 1, nodes = ns_ * nd_;
  struct Via {
    double cost;
    int j, node;
  };
  std::vector<Via> vias;
  for (int j = 1; j <= L; ++j)
    for (int n = 0; n < nodes; ++n)
      if (fwd_[j][n] < kInf && bwd_[j][n] < kInf) vias.push_back({fwd_[j][n] + bwd_[j][n], j, n});
  std::stable_sort(vias.begin(), vias.end(), [](const Via& a, const Via& b) { return a.cost < b.cost; });
  std::vector<GuidancePath> out;
  std::vector<int> labels;
  for (const Via& v : vias) {
    if (static_cast<int>(out.size()) >= max_classes) break;
    labels = lf_[v.j][v.node];
    const std::vector<int>& back = lb_[v.j][v.node];
    for (size_t i = 0; i < labels.size(); ++i) labels[i] += back[i];
    const Signature sig = make_signature(pb_, labels);
    if (std::any_of(out.begin(), out.end(), [&](const GuidancePath& p) { return same_class(p.signature, sig); }))
      continue;
    GuidancePath p = path_through(v.j, v.node);
    p.signature = sig;
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

namespace {

// True when no obstacle in both a and b has labels la, lb with clash(la, lb).
template <class Clash>
bool agree(const Signature& a, const Signature& b, Clash clash) {
  size_t i = 0, j = 0;
  while (i < a.labels.size() && j < b.labels.size()) {
    if (a.labels[i].first < b.labels[j].first) {
      ++i;
    } else if (b.labels[j].first < a.labels[i].first) {
      ++j;
    } else {
      if (clash(a.labels[i].second, b.labels[j].second)) return false;
      ++i;
      ++j;
    }
  }
  return true;
}

}  // namespace

bool same_class(const Signature& a, const Signature& b) {
  return agree(a, b, [](int la, int lb) { return la != lb; });
}

bool compatible(const Signature& a, const Signature& b) {
  return agree(a, b, [](int la, int lb) { return la != 0 && lb != 0 && la != lb; });
}

RouteFrame route_frame(const Problem& pb) {
  RouteFrame f;
  f.ox = pb.x0;
  f.oy = pb.y0;
  const double dx = pb.ref_x[pb.N] - pb.x0, dy = pb.ref_y[pb.N] - pb.y0, n = std::hypot(dx, dy);
  constexpr double kMinAxisM = 0.1;
  if (n >= kMinAxisM) {
    f.ex = dx / n;
    f.ey = dy / n;
  } else {
    const double yaw = pb.ref_yaw.size() > 1 ? pb.ref_yaw[1] : pb.yaw0;
    f.ex = std::cos(yaw);
    f.ey = std::sin(yaw);
  }
  return f;
}

Signature path_signature(const Problem& pb, const RouteFrame& f, const std::vector<double>& xs,
                         const std::vector<double>& ys) {
  std::vector<int> labels(pb.obstacles.size(), 0);
  add_labels(pb, f, 0, xs.data(), ys.data(), pb.N + 1, &labels);
  add_end_labels(pb, f, xs[pb.N], ys[pb.N], &labels);
  return make_signature(pb, labels);
}

Signature states_signature(const Problem& pb, const RouteFrame& f, const std::vector<double>& states) {
  std::vector<double> xs(pb.N + 1), ys(pb.N + 1);
  for (int k = 0; k <= pb.N; ++k) {
    xs[k] = states[3 * k];
    ys[k] = states[3 * k + 1];
  }
  return path_signature(pb, f, xs, ys);
}

std::vector<GuidancePath> find_guidance(const Problem& pb, const GuidanceParams& g) {
  if (g.max_classes <= 0 || pb.N < 1 || static_cast<int>(pb.ref_x.size()) != pb.N + 1) return {};
  Lattice lattice(pb, g);
  return lattice.classes(g.max_classes);
}

Problem along_guidance(const Problem& pb, const GuidancePath& path) {
  Problem out = pb;
  out.ref_x = path.x;
  out.ref_y = path.y;
  double yaw = pb.ref_yaw[0];
  out.ref_yaw[0] = yaw;
  for (int k = 1; k <= pb.N; ++k) {
    const double dx = path.x[k] - path.x[k - 1], dy = path.y[k] - path.y[k - 1];
    constexpr double kMinStepM = 1e-3;  // standing still: the heading stays
    if (std::hypot(dx, dy) > kMinStepM) yaw += wrap_angle(std::atan2(dy, dx) - yaw);
    out.ref_yaw[k] = yaw;
  }
  return out;
}

std::vector<double> controls_along(const Problem& pb, const GuidancePath& path) {
  // a unicycle steering at each step towards the path's next point, at the
  // speed that reaches it, within the limits (the rate limits too)
  std::vector<double> u(2 * pb.N);
  double x = pb.x0, y = pb.y0, yaw = pb.yaw0, v = pb.v_prev, w = pb.omega_prev;
  for (int k = 0; k < pb.N; ++k) {
    const int target = std::min(k + 2, pb.N);  // two steps ahead: a steadier heading
    const double dx = path.x[target] - x, dy = path.y[target] - y;
    const double dist = std::hypot(path.x[k + 1] - x, path.y[k + 1] - y);
    const double err = dist > 1e-3 ? wrap_angle(std::atan2(dy, dx) - yaw) : 0.0;
    const double dw = pb.lim.alpha * pb.dt;
    const double want_w = std::clamp(err / pb.dt, -pb.lim.omega_max, pb.lim.omega_max);
    w = std::min(std::max(want_w, w - dw), w + dw);
    const double want_v = std::clamp(std::max(0.0, dist * std::cos(err)) / pb.dt, pb.lim.v_min, pb.lim.v_max);
    v = std::min(std::max(want_v, v - pb.lim.decel * pb.dt), v + pb.lim.accel * pb.dt);
    u[2 * k] = v;
    u[2 * k + 1] = w;
    unicycle_step(v, w, pb.dt, &x, &y, &yaw);
  }
  return u;
}

}  // namespace evade::planning
