#include "planning/ipopt_solver.h"

#include <IpIpoptApplication.hpp>
#include <IpIpoptData.hpp>
#include <IpTNLP.hpp>
#include <cmath>

namespace evade::planning {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr Number kInf = 2e19;  // IPOPT's default "no bound"

// Variables: X_k = (x, y, theta) for k = 0..N at 3k, then U_k = (v, omega)
// at 3(N+1) + 2k. Constraints: 3N dynamics (= 0), 2N rate limits (ranges),
// M N barrier constraints (>= 0), of the footprint (problem.h): each depends
// on x, y and theta of its two steps.
class MpcNlp : public Ipopt::TNLP {
 public:
  // start_u: the controls to start from (empty: zeros); the states are
  // rolled out from them, so that the start meets the dynamics.
  MpcNlp(const Problem& pb, const std::vector<double>& start_u)
      : pb_(pb), N_(pb.N), M_(static_cast<int>(pb.obstacles.size())) {
    start_u_.assign(static_cast<size_t>(2 * N_), 0.0);
    for (size_t i = 0; i < start_u_.size() && i < start_u.size(); ++i) start_u_[i] = start_u[i];
    start_x_.resize(static_cast<size_t>(3 * (N_ + 1)));
    rollout(pb, start_u_.data(), start_x_.data());
  }

  std::vector<double> solution;
  int iterations = 0;

  int xi(int k) const { return 3 * k; }
  int ui(int k) const { return 3 * (N_ + 1) + 2 * k; }
  int n() const { return 3 * (N_ + 1) + 2 * N_; }
  int m() const { return 3 * N_ + 2 * N_ + M_ * N_; }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override {
    n = this->n();
    m = this->m();
    nnz_jac_g = N_ * (4 + 4 + 3) + (2 * N_ - 2) * 2 + 2 + M_ * N_ * 6;
    build_hessian_structure();
    nnz_h_lag = static_cast<Index>(h_rows_.size());
    style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = -kInf;
      x_u[i] = kInf;
    }
    // the start state is fixed
    x_l[0] = x_u[0] = pb_.x0;
    x_l[1] = x_u[1] = pb_.y0;
    x_l[2] = x_u[2] = pb_.yaw0;
    for (int k = 0; k < N_; ++k) {
      x_l[ui(k)] = pb_.lim.v_min;
      x_u[ui(k)] = pb_.lim.v_max;
      x_l[ui(k) + 1] = -pb_.lim.omega_max;
      x_u[ui(k) + 1] = pb_.lim.omega_max;
    }
    int r = 0;
    for (int k = 0; k < 3 * N_; ++k, ++r) g_l[r] = g_u[r] = 0.0;
    for (int k = 0; k < N_; ++k) {
      const double vp = k == 0 ? pb_.v_prev : 0.0, wp = k == 0 ? pb_.omega_prev : 0.0;
      g_l[r] = vp - pb_.lim.decel * pb_.dt;
      g_u[r] = vp + pb_.lim.accel * pb_.dt;
      ++r;
      g_l[r] = wp - pb_.lim.alpha * pb_.dt;
      g_u[r] = wp + pb_.lim.alpha * pb_.dt;
      ++r;
    }
    for (int j = 0; j < M_ * N_; ++j, ++r) {
      g_l[r] = 0.0;
      g_u[r] = kInf;
    }
    (void)m;
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index, bool init_lambda,
                          Number*) override {
    if (!init_x || init_z || init_lambda) return false;
    for (int i = 0; i < 3 * (N_ + 1); ++i) x[i] = start_x_[static_cast<size_t>(i)];
    for (int i = 0; i < 2 * N_; ++i) x[ui(0) + i] = start_u_[static_cast<size_t>(i)];
    (void)n;
    return true;
  }

  bool eval_f(Index, const Number* z, bool, Number& obj) override {
    obj = 0;
    for (int k = 0; k <= N_; ++k) {
      const bool term = k == N_;
      const double wxy = term ? pb_.w.p_xy : pb_.w.q_xy, wyaw = term ? pb_.w.p_yaw : pb_.w.q_yaw;
      const double ex = z[xi(k)] - pb_.ref_x[k], ey = z[xi(k) + 1] - pb_.ref_y[k];
      const double et = wrap_angle(z[xi(k) + 2] - pb_.ref_yaw[k]);
      obj += wxy * (ex * ex + ey * ey) + wyaw * et * et;
    }
    for (int k = 0; k < N_; ++k) {
      const double v = z[ui(k)], w = z[ui(k) + 1];
      obj += pb_.w.r_v * v * v + pb_.w.r_omega * w * w;
      if (k + 1 < N_) {
        const double dv = z[ui(k + 1)] - v, dw = z[ui(k + 1) + 1] - w;
        obj += pb_.w.s_v * dv * dv + pb_.w.s_omega * dw * dw;
      }
    }
    return true;
  }

  bool eval_grad_f(Index n, const Number* z, bool, Number* grad) override {
    for (Index i = 0; i < n; ++i) grad[i] = 0;
    for (int k = 0; k <= N_; ++k) {
      const bool term = k == N_;
      const double wxy = term ? pb_.w.p_xy : pb_.w.q_xy, wyaw = term ? pb_.w.p_yaw : pb_.w.q_yaw;
      grad[xi(k)] = 2 * wxy * (z[xi(k)] - pb_.ref_x[k]);
      grad[xi(k) + 1] = 2 * wxy * (z[xi(k) + 1] - pb_.ref_y[k]);
      grad[xi(k) + 2] = 2 * wyaw * wrap_angle(z[xi(k) + 2] - pb_.ref_yaw[k]);
    }
    for (int k = 0; k < N_; ++k) {
      grad[ui(k)] += 2 * pb_.w.r_v * z[ui(k)];
      grad[ui(k) + 1] += 2 * pb_.w.r_omega * z[ui(k) + 1];
      if (k + 1 < N_) {
        const double dv = z[ui(k + 1)] - z[ui(k)], dw = z[ui(k + 1) + 1] - z[ui(k) + 1];
        grad[ui(k + 1)] += 2 * pb_.w.s_v * dv;
        grad[ui(k)] -= 2 * pb_.w.s_v * dv;
        grad[ui(k + 1) + 1] += 2 * pb_.w.s_omega * dw;
        grad[ui(k) + 1] -= 2 * pb_.w.s_omega * dw;
      }
    }
    return true;
  }

  bool eval_g(Index, const Number* z, bool, Index, Number* g) override {
    int r = 0;
    for (int k = 0; k < N_; ++k) {
      const double th = z[xi(k) + 2], v = z[ui(k)], w = z[ui(k) + 1];
      g[r++] = z[xi(k + 1)] - z[xi(k)] - v * std::cos(th) * pb_.dt;
      g[r++] = z[xi(k + 1) + 1] - z[xi(k) + 1] - v * std::sin(th) * pb_.dt;
      g[r++] = z[xi(k + 1) + 2] - th - w * pb_.dt;
    }
    for (int k = 0; k < N_; ++k) {
      g[r++] = z[ui(k)] - (k == 0 ? 0.0 : z[ui(k - 1)]);
      g[r++] = z[ui(k) + 1] - (k == 0 ? 0.0 : z[ui(k - 1) + 1]);
    }
    for (int i = 0; i < M_; ++i) {
      const ObstacleTrack& o = pb_.obstacles[i];
      for (int k = 0; k < N_; ++k) {
        const double h1 = barrier_at(pb_, o, k + 1, z + xi(k + 1)).h;
        const double h0 = barrier_at(pb_, o, k, z + xi(k)).h;
        g[r++] = h1 - o.decay * h0;
      }
    }
    return true;
  }

  bool eval_jac_g(Index, const Number* z, bool, Index, Index, Index* iRow, Index* jCol, Number* values) override {
    int e = 0;
    if (values == nullptr) {
      int r = 0;
      for (int k = 0; k < N_; ++k) {
        for (int c : {xi(k + 1), xi(k), xi(k) + 2, ui(k)}) iRow[e] = r, jCol[e++] = c;
        ++r;
        for (int c : {xi(k + 1) + 1, xi(k) + 1, xi(k) + 2, ui(k)}) iRow[e] = r, jCol[e++] = c;
        ++r;
        for (int c : {xi(k + 1) + 2, xi(k) + 2, ui(k) + 1}) iRow[e] = r, jCol[e++] = c;
        ++r;
      }
      for (int k = 0; k < N_; ++k) {
        for (int d = 0; d < 2; ++d) {
          iRow[e] = r, jCol[e++] = ui(k) + d;
          if (k > 0) iRow[e] = r, jCol[e++] = ui(k - 1) + d;
          ++r;
        }
      }
      for (int i = 0; i < M_; ++i)
        for (int k = 0; k < N_; ++k) {
          for (int c : {xi(k + 1), xi(k + 1) + 1, xi(k + 1) + 2, xi(k), xi(k) + 1, xi(k) + 2})
            iRow[e] = r, jCol[e++] = c;
          ++r;
        }
      return true;
    }
    for (int k = 0; k < N_; ++k) {
      const double th = z[xi(k) + 2], v = z[ui(k)];
      const double c = std::cos(th), s = std::sin(th), dt = pb_.dt;
      values[e++] = 1;
      values[e++] = -1;
      values[e++] = v * s * dt;
      values[e++] = -c * dt;
      values[e++] = 1;
      values[e++] = -1;
      values[e++] = -v * c * dt;
      values[e++] = -s * dt;
      values[e++] = 1;
      values[e++] = -1;
      values[e++] = -dt;
    }
    for (int k = 0; k < N_; ++k)
      for (int d = 0; d < 2; ++d) {
        values[e++] = 1;
        if (k > 0) values[e++] = -1;
      }
    for (int i = 0; i < M_; ++i) {
      const ObstacleTrack& o = pb_.obstacles[i];
      for (int k = 0; k < N_; ++k) {
        const BarrierValue b1 = barrier_at(pb_, o, k + 1, z + xi(k + 1));
        const BarrierValue b0 = barrier_at(pb_, o, k, z + xi(k));
        values[e++] = b1.gx;
        values[e++] = b1.gy;
        values[e++] = b1.gth;
        values[e++] = -o.decay * b0.gx;
        values[e++] = -o.decay * b0.gy;
        values[e++] = -o.decay * b0.gth;
      }
    }
    return true;
  }

  bool eval_h(Index, const Number* z, bool, Number sigma, Index, const Number* lambda, bool, Index, Index* iRow,
              Index* jCol, Number* values) override {
    if (values == nullptr) {
      for (size_t e = 0; e < h_rows_.size(); ++e) {
        iRow[e] = h_rows_[e];
        jCol[e] = h_cols_[e];
      }
      return true;
    }
    for (size_t e = 0; e < h_rows_.size(); ++e) values[e] = 0;
    // objective (wrap has unit slope, zero curvature away from +-pi)
    for (int k = 0; k <= N_; ++k) {
      const bool term = k == N_;
      const double wxy = term ? pb_.w.p_xy : pb_.w.q_xy, wyaw = term ? pb_.w.p_yaw : pb_.w.q_yaw;
      values[hx_[k]] += sigma * 2 * wxy;
      values[hy_[k]] += sigma * 2 * wxy;
      values[ht_[k]] += sigma * 2 * wyaw;
    }
    for (int k = 0; k < N_; ++k) {
      double sv = 2 * pb_.w.r_v, sw = 2 * pb_.w.r_omega;
      if (k + 1 < N_) sv += 2 * pb_.w.s_v, sw += 2 * pb_.w.s_omega;
      if (k > 0) sv += 2 * pb_.w.s_v, sw += 2 * pb_.w.s_omega;
      values[hv_[k]] += sigma * sv;
      values[hw_[k]] += sigma * sw;
      if (k + 1 < N_) {
        values[hvv1_[k]] += sigma * -2 * pb_.w.s_v;
        values[hww1_[k]] += sigma * -2 * pb_.w.s_omega;
      }
    }
    // dynamics: -v cos(th) dt and -v sin(th) dt
    for (int k = 0; k < N_; ++k) {
      const double th = z[xi(k) + 2], v = z[ui(k)], dt = pb_.dt;
      const double lx = lambda[3 * k], ly = lambda[3 * k + 1];
      const double c = std::cos(th), s = std::sin(th);
      values[ht_[k]] += lx * (v * c * dt) + ly * (v * s * dt);
      values[hvt_[k]] += lx * (s * dt) + ly * (-c * dt);
    }
    // barriers
    const int base = 5 * N_;
    for (int i = 0; i < M_; ++i) {
      const ObstacleTrack& o = pb_.obstacles[i];
      for (int k = 0; k < N_; ++k) {
        const double l = lambda[base + i * N_ + k];
        if (l == 0) continue;
        add_barrier_hessian(barrier_at(pb_, o, k + 1, z + xi(k + 1), true), k + 1, l, values);
        if (o.decay != 0) add_barrier_hessian(barrier_at(pb_, o, k, z + xi(k), true), k, -l * o.decay, values);
      }
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* z, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities*) override {
    solution.assign(z, z + n);
    if (ip_data) iterations = ip_data->iter_count();
  }

 private:
  // scale times the barrier's second derivatives in (x, y, theta) at step k
  void add_barrier_hessian(const BarrierValue& b, int k, double scale, Number* values) const {
    values[hx_[k]] += scale * b.hxx;
    values[hyx_[k]] += scale * b.hxy;
    values[hy_[k]] += scale * b.hyy;
    values[htx_[k]] += scale * b.hxt;
    values[hty_[k]] += scale * b.hyt;
    values[ht_[k]] += scale * b.htt;
  }
  int add_h(int row, int col) {
    h_rows_.push_back(row);
    h_cols_.push_back(col);
    return static_cast<int>(h_rows_.size()) - 1;
  }
  // Lower triangle (row >= col) of the Lagrangian's Hessian.
  void build_hessian_structure() {
    if (!h_rows_.empty()) return;
    for (int k = 0; k <= N_; ++k) {
      hx_.push_back(add_h(xi(k), xi(k)));
      hyx_.push_back(add_h(xi(k) + 1, xi(k)));
      hy_.push_back(add_h(xi(k) + 1, xi(k) + 1));
      ht_.push_back(add_h(xi(k) + 2, xi(k) + 2));
      htx_.push_back(add_h(xi(k) + 2, xi(k)));
      hty_.push_back(add_h(xi(k) + 2, xi(k) + 1));
    }
    for (int k = 0; k < N_; ++k) {
      hvt_.push_back(add_h(ui(k), xi(k) + 2));
      hv_.push_back(add_h(ui(k), ui(k)));
      hw_.push_back(add_h(ui(k) + 1, ui(k) + 1));
      if (k + 1 < N_) {
        hvv1_.push_back(add_h(ui(k + 1), ui(k)));
        hww1_.push_back(add_h(ui(k + 1) + 1, ui(k) + 1));
      }
    }
  }

  const Problem& pb_;
  int N_, M_;
  std::vector<double> start_u_, start_x_;
  std::vector<Index> h_rows_, h_cols_;
  std::vector<int> hx_, hyx_, hy_, ht_, htx_, hty_, hvt_, hv_, hw_, hvv1_, hww1_;
};

}  // namespace

IpoptResult solve_with_ipopt(const Problem& pb, const IpoptOptions& opts) {
  IpoptResult out;
  Ipopt::SmartPtr<MpcNlp> nlp = new MpcNlp(pb, opts.start_u);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetIntegerValue("print_level", opts.print_level);
  o.SetStringValue("sb", "yes");
  o.SetNumericValue("tol", opts.tol);
  o.SetNumericValue("constr_viol_tol", opts.constr_viol_tol);
  o.SetNumericValue("compl_inf_tol", opts.compl_inf_tol);
  o.SetIntegerValue("max_iter", opts.max_iter);
  o.SetStringValue("hessian_approximation", opts.limited_memory ? "limited-memory" : "exact");
  o.SetNumericValue("mu_init", opts.mu_init);
  o.SetNumericValue("bound_push", opts.bound_push);
  o.SetNumericValue("bound_frac", opts.bound_push);
  if (app->Initialize() != Ipopt::Solve_Succeeded) return out;
  const Ipopt::ApplicationReturnStatus st = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(nlp)));
  out.status = static_cast<int>(st);
  out.solved = st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level;
  out.iterations = nlp->iterations;
  if (nlp->solution.empty()) return out;
  out.u.assign(nlp->solution.begin() + 3 * (pb.N + 1), nlp->solution.end());
  out.cost = objective(pb, out.u.data());
  out.max_violation = max_violation(pb, out.u.data());
  return out;
}

}  // namespace evade::planning
