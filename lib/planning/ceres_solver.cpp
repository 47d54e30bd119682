#include "planning/ceres_solver.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace evade::planning {
namespace {

// One constraint in the inner problem: index j and how it enters.
struct ActiveConstraint {
  int j;
  bool elastic;  // quadratic penalty on the violation instead of the AL term
};

// Relative ridge added to J^T J before its Cholesky factorization in the
// compressed inner cost (only matters when J^T J is singular).
constexpr double kCompressionRidge = 1e-12;

// Column bucket of the causal rank updates of J^T J (see accumulate_dense_rows).
constexpr int kWidthBucket = 10;

// The rollout of the unicycle and its forward sensitivities, from which
// every residual's Jacobian row follows by the chain rule (no autodiff).
// With th_k = yaw0 + dt sum_{j<k} w_j and p_k = p_0 + dt sum_{i<k} v_i (cos th_i, sin th_i):
//   dp_k/dv_j  = dt (cos th_j, sin th_j)                         j < k
//   dth_k/dw_j = dt                                              j < k
//   dp_k/dw_j  = sum_{i=j+1}^{k-1} v_i dt^2 (-sin th_i, cos th_i) = S_k - S_{j+1}   j < k
// with the prefix sums S_m = sum_{i<m} v_i dt^2 (-sin th_i, cos th_i).
// All derivatives are zero for j >= k (causality).
struct Rollout {
  std::vector<double> states;          // 3 (N + 1): x, y, yaw
  std::vector<double> cos_th, sin_th;  // N: at steps 0..N-1
  std::vector<double> sx, sy;          // N + 1: prefix sums S_m

  void compute(const Problem& pb, const double* u, bool with_sensitivities) {
    const int N = pb.N;
    states.resize(3 * (N + 1));
    // each step's cos and sin kept from the rollout for the sensitivities
    // and the footprint's headings
    cos_th.resize(N);
    sin_th.resize(N);
    rollout(pb, u, states.data(), cos_th.data(), sin_th.data());
    if (!with_sensitivities) return;
    sx.assign(N + 1, 0.0);
    sy.assign(N + 1, 0.0);
    const double dt2 = pb.dt * pb.dt;
    for (int i = 0; i < N; ++i) {
      sx[i + 1] = sx[i] - u[2 * i] * dt2 * sin_th[i];
      sy[i + 1] = sy[i] + u[2 * i] * dt2 * cos_th[i];
    }
  }

  // row += scale * d(gx x_k + gy y_k + gth th_k)/du
  void add_state_row(const Problem& pb, int k, double gx, double gy, double gth, double* row) const {
    const double dt = pb.dt;
    for (int j = 0; j < k; ++j) {
      row[2 * j] += dt * (gx * cos_th[j] + gy * sin_th[j]);
      row[2 * j + 1] += gx * (sx[k] - sx[j + 1]) + gy * (sy[k] - sy[j + 1]) + gth * dt;
    }
  }
};

// All residuals of one inner problem in one block over the 2N controls:
// the cost residuals of problem.h and one AL (or elastic) residual per
// active constraint, with analytic Jacobians (the rollout sensitivities
// above chained with the barrier gradient of problem.h). One O(N^2) pass.
class InnerCost : public ceres::CostFunction {
 public:
  InnerCost(const Problem& pb, std::vector<ActiveConstraint> active, const std::vector<double>& lambda, double rho,
            double elastic_penalty, double cost_weight = 1.0, bool compressed = true)
      : pb_(pb),
        active_(std::move(active)),
        lambda_(lambda),
        rho_(rho),
        mu_(elastic_penalty),
        cost_scale_(std::sqrt(cost_weight)) {
    penetration_rows_ = pb.penetration_weight > 0 ? static_cast<int>(pb.obstacles.size()) * pb.N : 0;
    full_rows_ = num_cost_residuals(pb) + static_cast<int>(active_.size()) + penetration_rows_;
    set_num_residuals(compressed ? pb.num_controls() + 1 : full_rows_);
    compressed_ = compressed;
    mutable_parameter_block_sizes()->push_back(pb.num_controls());
    // each predicted ellipse's orientation, once per solve stage instead of
    // once per evaluation (sin and cos were a tenth of the solve time)
    orientation_.resize(2 * pb.obstacles.size() * static_cast<size_t>(pb.N + 1));
    for (size_t i = 0; i < pb.obstacles.size(); ++i)
      for (int k = 0; k <= pb.N; ++k) {
        const size_t idx = i * static_cast<size_t>(pb.N + 1) + static_cast<size_t>(k);
        orientation_[2 * idx] = std::cos(pb.obstacles[i].theta[k]);
        orientation_[2 * idx + 1] = std::sin(pb.obstacles[i].theta[k]);
      }
  }

  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    double* jac = jacobians != nullptr ? jacobians[0] : nullptr;
    if (!compressed_) return evaluate_full(params[0], residuals, jac);
    // Ceres' Levenberg-Marquardt uses only |r|^2, J^T J and J^T r (and the
    // column norms of J for its Jacobi scaling, the diagonal of J^T J). With
    // J^T J = L L^T the n + 1 rows [L^T; 0] and residuals
    // [L^-1 J^T r; sqrt(|r|^2 - |L^-1 J^T r|^2)] give exactly these, so Ceres
    // works on a 51-row problem instead of several hundred rows, most of them
    // zero (constraints whose AL term is off).
    const int n = pb_.num_controls();
    if (!jac) return cost_only(params[0], residuals);
    if (!full_at(params[0])) return false;
    const Eigen::Map<const Eigen::VectorXd> r(full_r_.data(), full_rows_);
    const double rr = r.squaredNorm();
    std::fill(residuals, residuals + n + 1, 0.0);
    // J^T J and J^T r over the live rows only: the sparse ones (controls,
    // control changes, rate limits: at most two entries, recorded by
    // evaluate_full) added directly, the dense ones (tracking, barriers)
    // by rank updates.
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    Eigen::MatrixXd& A = normal_;
    A.setZero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    accumulate_sparse_rows(&A, &b);
    accumulate_dense_rows(&A, &b);
    // Controls held at a bound (see run_inner): decoupled with zero
    // gradient, so every LM step leaves them exactly where they are. This
    // does what a SubsetManifold would without Ceres multiplying every
    // Jacobian by the manifold's.
    for (int i : held_) {
      A.row(i).setZero();
      A.col(i).setZero();
      A(i, i) = 1.0;
      b[i] = 0.0;
    }
    // A tiny ridge keeps the factorization defined when some weights are zero.
    const double ridge = kCompressionRidge * std::max(1.0, A.diagonal().maxCoeff());
    A.diagonal().array() += ridge;
    Eigen::LLT<Eigen::MatrixXd>& llt = llt_;
    llt.compute(A);
    if (llt.info() != Eigen::Success) return false;
    const Eigen::VectorXd rc = llt.matrixL().solve(b);
    Eigen::Map<RowMajor>(jac, n + 1, n).setZero();
    Eigen::Map<RowMajor>(jac, n, n) = llt.matrixU();  // A = U^T U
    for (int i = 0; i < n; ++i) residuals[i] = rc[i];
    residuals[n] = std::sqrt(std::max(0.0, rr - rc.squaredNorm()));
    return std::isfinite(residuals[n]);
  }

  // J^T r of the full problem at u (the gradient of the inner objective's
  // half), without the J^T J that Evaluate builds: what held_at_bounds needs.
  bool gradient(const double* u, std::vector<double>* g) const {
    const int n = pb_.num_controls();
    if (!full_at(u)) return false;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    accumulate_sparse_rows(nullptr, &b);
    accumulate_dense_rows(nullptr, &b);
    g->assign(b.data(), b.data() + n);
    return true;
  }

 private:
  // The full residuals and Jacobian at u in full_r_ and full_j_ (and the
  // rows' kinds), evaluated unless the last evaluation was this one at the
  // same controls: held_at_bounds takes the gradient where Ceres then
  // starts, and where its last step ended.
  bool full_at(const double* u) const {
    const int n = pb_.num_controls();
    if (static_cast<int>(full_u_.size()) == n && std::equal(u, u + n, full_u_.begin())) return full_ok_;
    full_u_.assign(u, u + n);
    full_r_.resize(full_rows_);
    full_j_.resize(static_cast<size_t>(full_rows_) * n);
    full_ok_ = evaluate_full(u, full_r_.data(), full_j_.data());
    return full_ok_;
  }

  // The compressed residuals without the Jacobian: |r| in the last, the
  // others 0. Ceres' line search on a bounded problem evaluates the cost at
  // the point that it then evaluates again as the step's candidate; the
  // same controls give the same value, so the last one is kept.
  bool cost_only(const double* u, double* residuals) const {
    const int n = pb_.num_controls();
    std::fill(residuals, residuals + n + 1, 0.0);
    if (static_cast<int>(cost_u_.size()) != n || !std::equal(u, u + n, cost_u_.begin())) {
      cost_u_.assign(u, u + n);
      full_u_.clear();  // full_r_ and the rows' kinds are this evaluation's now
      full_r_.resize(full_rows_);
      cost_ok_ = evaluate_full(u, full_r_.data(), nullptr);
      cost_norm_ =
          cost_ok_ ? std::sqrt(Eigen::Map<const Eigen::VectorXd>(full_r_.data(), full_rows_).squaredNorm()) : 0.0;
    }
    residuals[n] = cost_norm_;
    return cost_ok_;
  }

  // J^T J (into *A unless null) and J^T r (into *b) of the live rows.
  void accumulate_sparse_rows(Eigen::MatrixXd* A, Eigen::VectorXd* b) const {
    const int n = pb_.num_controls();
    for (int row = 0; row < full_rows_; ++row) {
      if (live_[row] != kRowSparse) continue;
      const double* jr = full_j_.data() + static_cast<size_t>(row) * n;
      const int nz[2] = {nz_[2 * row], nz_[2 * row + 1]};
      for (int x : nz) {
        if (x < 0) continue;
        (*b)[x] += jr[x] * full_r_[row];
        if (!A) continue;
        for (int y : nz)
          if (y >= 0) (*A)(x, y) += jr[x] * jr[y];
      }
    }
  }

  // Dense rows are causal: the row of a state at step k depends only on the
  // controls before k (its first 2k columns). Rows are gathered in buckets
  // of kWidthBucket columns and each bucket updates only the leading block
  // of J^T J it touches, about a third of the flops of one update with all
  // rows over all columns.
  void accumulate_dense_rows(Eigen::MatrixXd* A, Eigen::VectorXd* b) const {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const int n = pb_.num_controls();
    const int buckets = (n + kWidthBucket - 1) / kWidthBucket;
    bucket_rows_.assign(buckets, {});
    for (int row = 0; row < full_rows_; ++row)
      if (live_[row] == kRowDense && width_[row] > 0) bucket_rows_[(width_[row] - 1) / kWidthBucket].push_back(row);
    Eigen::MatrixXd& D = dense_;
    if (A) D.setZero(n, n);
    for (int bk = 0; bk < buckets; ++bk) {
      const auto& rows = bucket_rows_[bk];
      if (rows.empty()) continue;
      const int w = std::min(n, (bk + 1) * kWidthBucket);
      block_.resize(static_cast<Eigen::Index>(rows.size()), w);
      block_r_.resize(static_cast<Eigen::Index>(rows.size()));
      for (size_t q = 0; q < rows.size(); ++q) {
        block_.row(static_cast<Eigen::Index>(q)) =
            Eigen::Map<const RowMajor>(full_j_.data() + static_cast<size_t>(rows[q]) * n, 1, w);
        block_r_[static_cast<Eigen::Index>(q)] = full_r_[rows[q]];
      }
      if (A) D.topLeftCorner(w, w).selfadjointView<Eigen::Lower>().rankUpdate(block_.transpose());
      b->head(w).noalias() += block_.transpose() * block_r_;
    }
    if (!A) return;
    D.triangularView<Eigen::StrictlyUpper>() = D.transpose();
    *A += D;
  }

  bool evaluate_full(const double* u, double* residuals, double* jac) const {
    const int n = pb_.num_controls(), N = pb_.N;
    ro_.compute(pb_, u, jac != nullptr);
    headings();
    // Each nearest disc is computed once per controls: an evaluation at the
    // controls of the last one (Ceres evaluates the Jacobian where its line
    // search has just evaluated the cost) takes those it computed.
    const size_t stages = pb_.obstacles.size() * static_cast<size_t>(N + 1);
    if (static_cast<int>(stage_u_.size()) != n || !std::equal(u, u + n, stage_u_.begin())) {
      stage_u_.assign(u, u + n);
      stage_.resize(stages);
      staged_.assign(stages, 0);
    }
    // Rows are zeroed as they are written (row_of): in the compressed form
    // only live rows are read, and most constraint rows are dead.
    if (jac && !compressed_) std::fill(jac, jac + static_cast<size_t>(full_rows_) * n, 0.0);
    live_.assign(full_rows_, kRowDense);
    nz_.assign(2 * static_cast<size_t>(full_rows_), -1);
    width_.assign(full_rows_, n);
    int r = cost_rows(u, residuals, jac);
    // barrier gradients h_i(X_k), each computed once although two
    // constraints (k-1 -> k and k -> k+1) use it, and only for live rows
    bar_.resize(stages);
    have_.assign(stages, 0);
    for (size_t a = 0; a < active_.size(); ++a, ++r) constraint_row(a, r, u, residuals, jac);
    r = penetration_rows(r, residuals, jac);
    for (int q = 0; q < r; ++q)
      if (!std::isfinite(residuals[q])) return false;
    return true;
  }

  // Row r of the Jacobian jac, zeroed unless the whole of jac was.
  double* row_of(double* jac, int r) const {
    const int n = pb_.num_controls();
    double* jr = jac + static_cast<size_t>(r) * n;
    if (compressed_) std::fill(jr, jr + n, 0.0);
    return jr;
  }

  // The cost residuals, in the order of cost_residuals() in problem.h, and
  // their Jacobian rows (jac: unless null); returns the next row.
  int cost_rows(const double* u, double* residuals, double* jac) const {
    const int n = pb_.num_controls(), N = pb_.N;
    const double* xs = ro_.states.data();
    auto row = [&](int r) { return row_of(jac, r); };
    int r = 0;
    const double sq_xy = std::sqrt(pb_.w.q_xy), sq_yaw = std::sqrt(pb_.w.q_yaw);
    for (int k = 1; k <= N; ++k) {
      const bool terminal = k == N;
      const double wxy = cost_scale_ * (terminal ? std::sqrt(pb_.w.p_xy) : sq_xy);
      const double wyaw = cost_scale_ * (terminal ? std::sqrt(pb_.w.p_yaw) : sq_yaw);
      residuals[r] = wxy * (xs[3 * k] - pb_.ref_x[k]);
      residuals[r + 1] = wxy * (xs[3 * k + 1] - pb_.ref_y[k]);
      residuals[r + 2] = wyaw * wrap_angle(xs[3 * k + 2] - pb_.ref_yaw[k]);  // d wrap(e)/de = 1
      width_[r] = width_[r + 1] = width_[r + 2] = 2 * k;  // the state at k depends on the controls before k
      if (jac) {
        ro_.add_state_row(pb_, k, wxy, 0, 0, row(r));
        ro_.add_state_row(pb_, k, 0, wxy, 0, row(r + 1));
        ro_.add_state_row(pb_, k, 0, 0, wyaw, row(r + 2));
      }
      r += 3;
    }
    const double sr[2] = {cost_scale_ * std::sqrt(pb_.w.r_v), cost_scale_ * std::sqrt(pb_.w.r_omega)};
    std::fill(live_.begin() + r, live_.begin() + r + n + (n - 2), kRowSparse);
    for (int i = 0; i < n; ++i, ++r) {
      residuals[r] = sr[i % 2] * u[i];
      nz_[2 * r] = i;
      if (jac) row(r)[i] = sr[i % 2];
    }
    const double ss[2] = {cost_scale_ * std::sqrt(pb_.w.s_v), cost_scale_ * std::sqrt(pb_.w.s_omega)};
    for (int i = 0; i + 2 < n; ++i, ++r) {
      residuals[r] = ss[i % 2] * (u[i + 2] - u[i]);
      nz_[2 * r] = i;
      nz_[2 * r + 1] = i + 2;
      if (jac) {
        double* jr = row(r);
        jr[i + 2] = ss[i % 2];
        jr[i] = -ss[i % 2];
      }
    }
    return r;
  }

  // The cosine and sine of the rollout's heading at every step, once for
  // every obstacle (1 and 0 for a point robot, whose h ignores the heading):
  // the rollout's own up to step N - 1.
  void headings() const {
    const double* xs = ro_.states.data();
    const bool point = is_point(pb_.footprint);
    const int N = pb_.N;
    heading_.resize(2 * static_cast<size_t>(N + 1));
    for (int k = 0; k <= N; ++k) {
      heading_[2 * k] = point ? 1.0 : k < N ? ro_.cos_th[k] : std::cos(xs[3 * k + 2]);
      heading_[2 * k + 1] = point ? 0.0 : k < N ? ro_.sin_th[k] : std::sin(xs[3 * k + 2]);
    }
  }

  // The nearest disc of obstacle i to the rollout's state k, computed on
  // first use at these controls (an obstacle of the static field has none:
  // its value and gradient come together, in bar_).
  const FootprintStage& stage_of(int i, int k) const {
    const double* xs = ro_.states.data();
    const size_t idx = static_cast<size_t>(i) * (pb_.N + 1) + k;
    if (!staged_[idx]) {
      const ObstacleTrack& o = pb_.obstacles[i];
      stage_[idx] =
          footprint_stage(xs[3 * k], xs[3 * k + 1], heading_[2 * k], heading_[2 * k + 1], o.x[k], o.y[k], o.a[k],
                          o.b[k], orientation_[2 * idx], orientation_[2 * idx + 1], pb_.footprint, pb_.d_safe);
      staged_[idx] = 1;
    }
    return stage_[idx];
  }

  // h_i(X_k) of the current rollout.
  double value_of(int i, int k) const {
    if (pb_.obstacles[i].field) return barrier_of(i, k).h;
    return stage_of(i, k).h;
  }

  // h_i(X_k) and its derivatives, computed on first use: rows that are
  // written to the Jacobian ask for them, every other use takes value_of.
  const BarrierValue& barrier_of(int i, int k) const {
    const size_t idx = static_cast<size_t>(i) * (pb_.N + 1) + k;
    if (have_[idx]) return bar_[idx];
    const ObstacleTrack& o = pb_.obstacles[i];
    if (o.field)
      bar_[idx] = barrier_at(pb_, o, k, ro_.states.data() + 3 * k);  // static_field.h
    else
      bar_[idx] = footprint_derivatives(stage_of(i, k), heading_[2 * k], heading_[2 * k + 1], o.a[k], o.b[k],
                                        orientation_[2 * idx], orientation_[2 * idx + 1]);
    have_[idx] = 1;
    return bar_[idx];
  }

  // The nearest disc of the robot at step k to obstacle i at step k + 1
  // (the fallback's own-motion links, Problem::own_motion), and its h and
  // derivatives.
  FootprintStage own_motion_stage(int i, int k) const {
    const double* xs = ro_.states.data();
    const ObstacleTrack& o = pb_.obstacles[i];
    const size_t idx = static_cast<size_t>(i) * (pb_.N + 1) + k + 1;
    return footprint_stage(xs[3 * k], xs[3 * k + 1], heading_[2 * k], heading_[2 * k + 1], o.x[k + 1], o.y[k + 1],
                           o.a[k + 1], o.b[k + 1], orientation_[2 * idx], orientation_[2 * idx + 1], pb_.footprint,
                           pb_.d_safe);
  }
  BarrierValue own_motion_derivatives(int i, int k, const FootprintStage& t) const {
    const ObstacleTrack& o = pb_.obstacles[i];
    const size_t idx = static_cast<size_t>(i) * (pb_.N + 1) + k + 1;
    return footprint_derivatives(t, heading_[2 * k], heading_[2 * k + 1], o.a[k + 1], o.b[k + 1], orientation_[2 * idx],
                                 orientation_[2 * idx + 1]);
  }

  // The second term of barrier link (i, k): decay h(X_k, O_k), or in the
  // own-motion form decay' h(X_k, O_k+1) (problem.h). Its h, its factor
  // (*coef), and (link_start_derivatives) its derivatives.
  struct LinkStart {
    double h = 0, coef = 0;
    FootprintStage own;  // the own-motion form's nearest disc
  };
  LinkStart link_start(int i, int k) const {
    const ObstacleTrack& o = pb_.obstacles[i];
    LinkStart s;
    if (!pb_.own_motion || o.field) {
      s.h = value_of(i, k);
      s.coef = pb_.own_motion && s.h <= 0.0 ? 1.0 : o.decay;
      return s;
    }
    s.own = own_motion_stage(i, k);
    s.h = s.own.h;
    s.coef = s.h <= 0.0 ? 1.0 : o.decay;
    return s;
  }
  BarrierValue link_start_derivatives(int i, int k, const LinkStart& s) const {
    if (!pb_.own_motion || pb_.obstacles[i].field) return barrier_of(i, k);
    return own_motion_derivatives(i, k, s.own);
  }

  // Rows from r: sqrt(penetration_weight) min(0, h_i(X_k)) for every
  // obstacle i and step k = 1..N (Problem::penetration_weight); returns
  // the next row.
  int penetration_rows(int r, double* residuals, double* jac) const {
    if (penetration_rows_ == 0) return r;
    const int N = pb_.N;
    const double w = std::sqrt(pb_.penetration_weight);
    for (int i = 0; i < static_cast<int>(pb_.obstacles.size()); ++i)
      for (int k = 1; k <= N; ++k, ++r) {
        const double h = value_of(i, k);
        residuals[r] = h < 0 ? w * h : 0.0;
        if (h >= 0) {
          live_[r] = kRowDead;
          continue;
        }
        width_[r] = 2 * k;
        if (!jac) continue;
        const BarrierValue& b = barrier_of(i, k);
        ro_.add_state_row(pb_, k, w * b.gx, w * b.gy, w * b.gth, row_of(jac, r));
      }
    return r;
  }

  // Row r: the AL (or elastic) residual of active constraint a, and its
  // Jacobian row (jac: unless null).
  void constraint_row(size_t a, int r, const double* u, double* residuals, double* jac) const {
    const int N = pb_.N, R = pb_.num_rate_constraints();
    const int j = active_[a].j;
    double g;
    // dg/du = sum of (coefficient, state step, gradient) terms, or linear in u
    ReachValue rv;    // a reach bound's value and derivatives
    LinkStart start;  // a barrier link's second term
    const bool reach = j >= R + pb_.num_barrier_constraints();
    if (reach) {
      const int c = j - R - pb_.num_barrier_constraints(), k = c % N;
      const double* x = ro_.states.data() + 3 * k;
      rv = reach_value_cs(pb_.reach[c / N], k, x[0], x[1], ro_.cos_th[k], ro_.sin_th[k], u[2 * k], jac != nullptr);
      g = rv.g;
      if (!pb_.relax.empty()) g += pb_.relax[j];
    } else if (j < R) {
      g = constraint(pb_, ro_.states.data(), u, j);
    } else {
      const int i = (j - R) / N, k = (j - R) % N;
      const ObstacleTrack& o = pb_.obstacles[i];
      g = value_of(i, k + 1);
      if (o.decay != 0.0 || pb_.own_motion) {
        start = link_start(i, k);
        g -= start.coef * start.h;
      }
      if (!pb_.relax.empty()) g += pb_.relax[j];
    }
    // residual = coef * g + offset when switched on, 0 otherwise
    double coef = 0, offset = 0;
    if (active_[a].elastic) {
      if (g < 0) coef = -std::sqrt(mu_);
    } else if (lambda_[j] / rho_ - g > 0) {
      coef = -std::sqrt(rho_);
      offset = std::sqrt(rho_) * lambda_[j] / rho_;
    }
    residuals[r] = coef == 0 ? 0.0 : coef * g + offset;
    if (coef == 0)
      live_[r] = kRowDead;
    else if (j < R)
      live_[r] = kRowSparse;
    if (!jac || coef == 0) return;
    double* jr = row_of(jac, r);
    if (j < R) {
      const int k = j / 4, which = j % 4;
      const int c = which < 2 ? 0 : 1;
      const double s = which % 2 == 0 ? -1.0 : 1.0;  // g = up - (now - prev) or (now - prev) + down
      jr[2 * k + c] += coef * s;
      nz_[2 * r] = 2 * k + c;
      if (k > 0) {
        jr[2 * (k - 1) + c] -= coef * s;
        nz_[2 * r + 1] = 2 * (k - 1) + c;
      }
    } else if (reach) {
      const int k = (j - R) % N;
      width_[r] = 2 * (k + 1);
      ro_.add_state_row(pb_, k, coef * rv.gx, coef * rv.gy, coef * rv.gth, jr);
      jr[2 * k] += coef * rv.gv;
    } else {
      const int i = (j - R) / N, k = (j - R) % N;
      const ObstacleTrack& o = pb_.obstacles[i];
      const BarrierValue& b1 = barrier_of(i, k + 1);
      width_[r] = 2 * (k + 1);
      ro_.add_state_row(pb_, k + 1, coef * b1.gx, coef * b1.gy, coef * b1.gth, jr);
      if (o.decay != 0.0 || pb_.own_motion) {
        const BarrierValue b0 = link_start_derivatives(i, k, start);
        const double d = -coef * start.coef;
        ro_.add_state_row(pb_, k, d * b0.gx, d * b0.gy, d * b0.gth, jr);
      }
    }
  }

  const Problem& pb_;
  std::vector<ActiveConstraint> active_;
  const std::vector<double>& lambda_;
  double rho_;
  double mu_;
  double cost_scale_;
  // scratch (Ceres evaluates one cost function from one thread here)
  mutable Rollout ro_;
  std::vector<double> orientation_;  // cos, sin of theta per obstacle and step (index i (N + 1) + k)
  mutable std::vector<BarrierValue> bar_;
  mutable std::vector<double> full_u_;         // the controls of full_r_ and full_j_ (full_at) ...
  mutable bool full_ok_ = false;               // ... and whether that evaluation succeeded
  mutable std::vector<double> cost_u_;         // the controls of the last cost_only evaluation ...
  mutable double cost_norm_ = 0;               // ... its |r| ...
  mutable bool cost_ok_ = false;               // ... and whether it succeeded
  mutable std::vector<double> stage_u_;        // the controls of stage_ ...
  mutable std::vector<FootprintStage> stage_;  // ... the nearest disc of each obstacle and step computed there
  mutable std::vector<char> staged_;           // ... where it was
  mutable std::vector<double> heading_;        // cos, sin of the heading at each step (headings())
  mutable std::vector<char> have_;             // bar_ computed in this evaluation
  // per full row: zero, at most two nonzero Jacobian entries, or dense
  static constexpr char kRowDead = 0, kRowSparse = 1, kRowDense = 2;
  mutable std::vector<char> live_;
  mutable std::vector<int> nz_;     // sparse rows: their (at most two) nonzero columns, -1 for none
  mutable std::vector<int> width_;  // dense rows: only the first width_ columns can be nonzero
  mutable std::vector<double> full_r_, full_j_;
  mutable std::vector<std::vector<int>> bucket_rows_;
  mutable Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> block_;
  mutable Eigen::VectorXd block_r_;
  mutable Eigen::MatrixXd normal_, dense_;   // Evaluate's J^T J and its dense rows' part
  mutable Eigen::LLT<Eigen::MatrixXd> llt_;  // and its factorization
  int full_rows_ = 0;
  int penetration_rows_ = 0;  // Problem::penetration_weight: one per obstacle and step
  bool compressed_ = true;
  std::vector<int> held_;  // controls held at their bound (compressed form only)

 public:
  void set_held(const std::vector<int>& held) { held_ = held; }
};

// Inner solves repeated at most this often while the set of controls held
// at their bounds changes.
constexpr int kMaxHeldRounds = 3;

// Multiplier estimate: AL residuals switched on by this lambda (rho = 1),
// active-set rounds, and relative ridge of the least-squares fit.
constexpr double kEstimateSwitchOn = 1e9;
constexpr int kEstimateRounds = 5;
constexpr double kEstimateRidge = 1e-8;

// A control within this fraction of its range from a bound counts as on it.
constexpr double kAtBound = 1e-9;

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// Lower and upper bound of control i: the box, and for k = 0 also the rate
// limits from the measured controls (a plain box on u_0, so it is exact).
void control_bounds(const Problem& pb, int i, double* lo, double* hi) {
  const bool is_v = i % 2 == 0;
  *lo = is_v ? pb.lim.v_min : -pb.lim.omega_max;
  *hi = is_v ? pb.lim.v_max : pb.lim.omega_max;
  if (i < 2) {
    const double prev = std::clamp(is_v ? pb.v_prev : pb.omega_prev, *lo, *hi);
    *lo = std::max(*lo, prev - (is_v ? pb.lim.decel : pb.lim.alpha) * pb.dt);
    *hi = std::min(*hi, prev + (is_v ? pb.lim.accel : pb.lim.alpha) * pb.dt);
  }
  if (is_v && size_t(i / 2) < pb.v_cap.size()) *hi = std::max(*lo, std::min(*hi, pb.v_cap[size_t(i / 2)]));
  if (!is_v) narrow_to_turn_bounds(pb, i / 2, lo, hi);
}

void set_bounds(const Problem& pb, ceres::Problem* problem, double* u) {
  for (int i = 0; i < pb.num_controls(); ++i) {
    double lo, hi;
    control_bounds(pb, i, &lo, &hi);
    problem->SetParameterLowerBound(u, i, lo);
    problem->SetParameterUpperBound(u, i, hi);
  }
}

ceres::Solver::Options inner_options(const SolverOptions& o, int max_iterations) {
  ceres::Solver::Options opt;
  opt.linear_solver_type = o.linear_solver == LinearSolver::kDenseQr ? ceres::DENSE_QR : ceres::DENSE_NORMAL_CHOLESKY;
  opt.max_num_iterations = max_iterations;
  opt.function_tolerance = o.inner_function_tolerance;
  opt.parameter_tolerance = o.inner_parameter_tolerance;
  opt.minimizer_progress_to_stdout = false;
  opt.logging_type = ceres::SILENT;
  opt.num_threads = 1;
  switch (o.line_search_interpolation) {
    case LineSearchInterpolation::kBisection:
      opt.line_search_interpolation_type = ceres::BISECTION;
      break;
    case LineSearchInterpolation::kQuadratic:
      opt.line_search_interpolation_type = ceres::QUADRATIC;
      break;
    case LineSearchInterpolation::kCubic:
      opt.line_search_interpolation_type = ceres::CUBIC;
      break;
  }
  return opt;
}

// Bisections of the segment from the best feasible iterate to the last one.
constexpr int kSegmentBisections = 12;

// Shortest step fraction tried by a projection step's backtracking.
constexpr double kProjectionMinStep = 1e-7;

// Whether control i at value ui sits on its bound: -1 lower, +1 upper, 0 inside.
int on_bound(const Problem& pb, int i, double ui) {
  double lo, hi;
  control_bounds(pb, i, &lo, &hi);
  const double eps = kAtBound * std::max(1.0, hi - lo);
  return ui <= lo + eps ? -1 : ui >= hi - eps ? 1 : 0;
}

// Whether moving control i by `direction` from ui would leave its box.
bool pushed_out(const Problem& pb, int i, double ui, double direction) {
  const int side = on_bound(pb, i, ui);
  return (side < 0 && direction < 0) || (side > 0 && direction > 0);
}

// Indices of the controls sitting on a bound with the inner objective's
// gradient pointing out of the box (a descent step, -grad, would leave it).
std::vector<int> held_at_bounds(const Problem& pb, const InnerCost& cost, const std::vector<double>& u) {
  const int n = pb.num_controls();
  std::vector<double> grad;
  std::vector<int> held;
  if (!cost.gradient(u.data(), &grad)) return held;
  for (int i = 0; i < n; ++i)
    if (pushed_out(pb, i, u[i], -grad[i])) held.push_back(i);
  return held;
}

// Rows of the full inner Jacobian at u for the constraints `js` with their
// AL residuals switched on (rho = 1, lambda large), i.e. -grad g_j each,
// after the cost residuals (num_cost_residuals rows). Also the residuals.
bool switched_on_jacobian(const Problem& pb, const std::vector<double>& u, const std::vector<int>& js,
                          std::vector<double>* residuals, std::vector<double>* jac) {
  std::vector<ActiveConstraint> active;
  for (int j : js) active.push_back({j, false});
  const std::vector<double> on(pb.num_constraints(), kEstimateSwitchOn);
  InnerCost cost(pb, std::move(active), on, 1.0, 1.0, 1.0, /*compressed=*/false);
  residuals->assign(cost.num_residuals(), 0.0);
  jac->assign(static_cast<size_t>(cost.num_residuals()) * pb.num_controls(), 0.0);
  const double* params[] = {u.data()};
  double* jacs[] = {jac->data()};
  return cost.Evaluate(params, residuals->data(), jacs);
}

// One inner solve: bounds as parameter bounds, controls pushed against a
// bound held there (see held_at_bounds). Takes ownership of cost. Returns
// the Ceres iterations used: at most round_iterations per Ceres solve and
// max_iterations in all (the rounds below re-solve).
int run_inner(const Problem& pb, const SolverOptions& o, InnerCost* cost_in, std::vector<double>* u,
              int round_iterations, int max_iterations, double* trust_radius = nullptr) {
  const int n = pb.num_controls();
  const std::unique_ptr<InnerCost> cost(cost_in);
  int iterations = 0;
  std::vector<int> held_before;
  // Controls on a bound that the gradient pushes outward are held there
  // (an active set): Ceres' projected trust-region steps on such
  // coordinates make the model's predicted decrease wrong and the steps
  // collapse. After a solve the set is re-examined: a held control whose
  // gradient now points into the box is released and the solve repeated
  // (else a control pinned at the start, e.g. u_0 at its rate bound from
  // a poor warm start, would stay there when the loop ends at once).
  for (int round = 0; round < kMaxHeldRounds && iterations < max_iterations; ++round) {
    cost->set_held({});
    const std::vector<int> held = held_at_bounds(pb, *cost, *u);
    if (round > 0 && held == held_before) break;
    if (static_cast<int>(held.size()) >= n) break;
    ceres::Problem::Options popt;
    popt.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    problem.AddResidualBlock(cost.get(), nullptr, u->data());
    set_bounds(pb, &problem, u->data());
    cost->set_held(held);
    ceres::Solver::Summary summary;
    ceres::Solver::Options opt = inner_options(o, std::min(round_iterations, max_iterations - iterations));
    // Carry the trust region over between outer iterations: restarting at
    // Ceres' default radius takes Gauss-Newton-sized steps across the kinks
    // of the AL terms, most of them rejected.
    if (trust_radius && *trust_radius > 0) opt.initial_trust_region_radius = *trust_radius;
    ceres::Solve(opt, &problem, &summary);
    if (trust_radius && !summary.iterations.empty())
      *trust_radius = std::max(o.min_trust_radius, summary.iterations.back().trust_region_radius);
    // steps taken: Ceres' iteration 0 is the evaluation at the start (and
    // counts as a successful step in its summary)
    iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    if (held.empty()) break;
    held_before = held;
  }
  return iterations;
}

// First-order multiplier estimate at u (the warm start): the lambda >= 0
// that best explains the gradient of J/2 by the gradients of the nearly
// active constraints (g_j < margin), grad(J/2) = sum_j lambda_j grad g_j,
// over the controls not on a bound, in the least-squares sense, negative
// ones dropped and the rest refitted (a few active-set rounds). With the
// previous plan as the warm start this puts the first inner problem next to
// the answer instead of at the unconstrained optimum (lambda = 0), which
// the AL loop would otherwise approach from far away.
void estimate_multipliers(const Problem& pb, const std::vector<double>& u, double margin, std::vector<double>* lambda) {
  const int n = pb.num_controls(), m = pb.num_constraints();
  std::vector<double> states, g;
  evaluate_constraints(pb, u.data(), &states, &g);
  std::vector<int> near;
  for (int j = 4; j < m; ++j)  // j < 4: the rate limits at k = 0 are bounds on u_0
    if (g[j] < margin) near.push_back(j);
  if (near.empty()) return;
  // gradient of J/2 and of every near constraint
  std::vector<double> r, jac;
  if (!switched_on_jacobian(pb, u, near, &r, &jac)) return;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int nc = num_cost_residuals(pb), nn = static_cast<int>(near.size());
  const Eigen::Map<const RowMajor> J(jac.data(), static_cast<Eigen::Index>(r.size()), n);
  const Eigen::VectorXd grad = J.topRows(nc).transpose() * Eigen::Map<const Eigen::VectorXd>(r.data(), nc);
  // grad g_j = -(row of constraint j); only controls strictly inside their box
  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (on_bound(pb, i, u[i]) == 0) free.push_back(i);
  std::vector<char> keep(nn, 1);
  Eigen::VectorXd est = Eigen::VectorXd::Zero(nn);
  for (int round = 0; round < kEstimateRounds; ++round) {
    std::vector<int> cols;
    for (int c = 0; c < nn; ++c)
      if (keep[c]) cols.push_back(c);
    if (cols.empty()) break;
    Eigen::MatrixXd A(free.size(), cols.size());
    Eigen::VectorXd b(free.size());
    for (size_t fi = 0; fi < free.size(); ++fi) {
      b[fi] = grad[free[fi]];
      for (size_t c = 0; c < cols.size(); ++c) A(fi, c) = -J(nc + cols[c], free[fi]);
    }
    // ridge: nearly dependent constraints (two obstacles' CBF chains) get
    // shared multipliers rather than huge opposite ones
    Eigen::MatrixXd AtA = A.transpose() * A;
    AtA.diagonal().array() += kEstimateRidge * std::max(1.0, AtA.diagonal().maxCoeff());
    const Eigen::VectorXd x = AtA.ldlt().solve(A.transpose() * b);
    est.setZero();
    bool negative = false;
    for (size_t c = 0; c < cols.size(); ++c) {
      if (!std::isfinite(x[c])) return;
      if (x[c] < 0) {
        keep[cols[c]] = 0;
        negative = true;
      } else {
        est[cols[c]] = x[c];
      }
    }
    if (!negative) break;
  }
  for (int c = 0; c < nn; ++c) (*lambda)[near[c]] = est[c];
}

// Projection onto the constraints (the final step of ALTRO's augmented
// Lagrangian): Gauss-Newton on the AL residuals leaves out the curvature
// term lambda_j grad^2 g_j of the Lagrangian, which is large on an active
// D-CBF chain (big multipliers, distance functions curved around the
// obstacle), so the outer loop can creep and end a few mm outside the
// tolerance. From that point, damped minimum-norm Newton steps that lift
// the violated constraints to a small margin (projection_target_m), over the
// controls not held on a bound, each shortened until the summed squared
// violation falls, reach the feasible set nearby and keep nearly all of the
// loop's progress. Returns true when u meets every constraint within
// target_violation.
bool project_onto_constraints(const Problem& pb, const SolverOptions& o, std::vector<double>* u) {
  const int n = pb.num_controls(), m = pb.num_constraints();
  // summed squared violation, the backtracking's merit
  auto squared_violation = [](const std::vector<double>& gg) {
    double s2 = 0;
    for (double v : gg) s2 += v < 0 ? v * v : 0.0;
    return s2;
  };
  std::vector<double> states, g, trial_g;
  evaluate_constraints(pb, u->data(), &states, &g);  // g always belongs to *u
  for (int it = 0; it <= o.projection_iterations; ++it) {
    double violation = 0;
    for (double v : g) violation = std::max(violation, -v);
    if (!std::isfinite(violation)) return false;
    if (violation <= o.target_violation) return true;
    if (it == o.projection_iterations) break;
    std::vector<int> near;
    for (int j = 4; j < m; ++j)  // j < 4: the rate limits at k = 0 are bounds on u_0
      if (g[j] < o.projection_target_m) near.push_back(j);
    std::vector<double> r, jac;  // constraint rows: -grad g_j
    if (!switched_on_jacobian(pb, *u, near, &r, &jac)) return false;
    // Minimum-norm step over the controls, those on a bound that it would
    // push outward taken out and the step recomputed (each round takes at
    // least one out, so this ends).
    const int nc = num_cost_residuals(pb), na = static_cast<int>(near.size());
    if (na == 0) return false;
    Eigen::VectorXd dg(na);
    for (int a = 0; a < na; ++a)
      dg[a] = std::max(0.0, o.projection_target_m - g[near[a]]);  // violated ones to the margin
    std::vector<int> free(n);
    for (int i = 0; i < n; ++i) free[i] = i;
    Eigen::VectorXd step;
    while (true) {
      const int nf = static_cast<int>(free.size());
      if (nf == 0) return false;
      Eigen::MatrixXd C(na, nf);
      for (int a = 0; a < na; ++a)
        for (int f = 0; f < nf; ++f) C(a, f) = -jac[static_cast<size_t>(nc + a) * n + free[f]];
      Eigen::MatrixXd CCt = C * C.transpose();
      // damped (Levenberg-Marquardt): links of one chain with a rate limit
      // can be nearly dependent, and the plain minimum-norm step is then
      // far longer than its linearization holds
      CCt.diagonal().array() += o.projection_damping * std::max(1.0, CCt.diagonal().maxCoeff());
      step = C.transpose() * CCt.ldlt().solve(dg);
      std::vector<int> keep;
      for (int f = 0; f < nf; ++f)
        if (!pushed_out(pb, free[f], (*u)[free[f]], step[f])) keep.push_back(free[f]);
      if (keep.size() == free.size()) break;
      free = keep;
    }
    const int nf = static_cast<int>(free.size());
    if (!step.allFinite()) return false;
    // Backtracking on the summed squared violation: near-dependent rows
    // (consecutive links of one chain, a barrier and a rate limit) can make
    // the full step far too long for the linearization.
    const double merit0 = squared_violation(g);
    std::vector<double> trial(*u);
    bool moved = false;
    for (double alpha = 1.0; alpha >= kProjectionMinStep; alpha *= 0.5) {
      for (int f = 0; f < nf; ++f) {
        double lo, hi;
        control_bounds(pb, free[f], &lo, &hi);
        trial[free[f]] = std::clamp((*u)[free[f]] + alpha * step[f], lo, hi);
      }
      evaluate_constraints(pb, trial.data(), &states, &trial_g);
      if (squared_violation(trial_g) < merit0) {
        moved = true;
        break;
      }
    }
    if (!moved) return false;
    *u = trial;
    g.swap(trial_g);
  }
  return false;
}

}  // namespace

void evaluate_result(const Problem& pb, const SolverOptions& o, SolveResult* r) {
  std::vector<double> g;
  evaluate_constraints(pb, r->u.data(), &r->states, &g);
  r->max_violation = 0;
  for (double v : g) r->max_violation = std::max(r->max_violation, -v);
  r->cost = objective(pb, r->u.data());
  r->min_barrier = min_barrier(pb, r->states);
  r->finite = all_finite(r->u) && all_finite(r->states) && std::isfinite(r->cost) && std::isfinite(r->max_violation);
  r->feasible = r->finite && r->max_violation <= o.constraint_tolerance;
}

bool evaluate_inner_residuals(const Problem& pb, const double* u, const std::vector<double>& lambda, double rho,
                              std::vector<double>* residuals, std::vector<double>* jacobian) {
  std::vector<ActiveConstraint> active;
  for (int j = 0; j < pb.num_constraints(); ++j) active.push_back({j, false});
  InnerCost cost(pb, std::move(active), lambda, rho, /*elastic_penalty=*/1.0, 1.0, /*compressed=*/false);
  residuals->assign(cost.num_residuals(), 0.0);
  double* jacs[] = {nullptr};
  if (jacobian) {
    jacobian->assign(static_cast<size_t>(cost.num_residuals()) * pb.num_controls(), 0.0);
    jacs[0] = jacobian->data();
  }
  const double* params[] = {u};
  return cost.Evaluate(params, residuals->data(), jacobian ? jacs : nullptr);
}

void project_controls(const Problem& pb, std::vector<double>* u) {
  u->resize(pb.num_controls(), 0.0);
  double v_prev = std::clamp(pb.v_prev, pb.lim.v_min, pb.lim.v_max);
  double w_prev = std::clamp(pb.omega_prev, -pb.lim.omega_max, pb.lim.omega_max);
  for (int k = 0; k < pb.N; ++k) {
    double& v = (*u)[2 * k];
    double& w = (*u)[2 * k + 1];
    if (!std::isfinite(v)) v = v_prev;
    if (!std::isfinite(w)) w = w_prev;
    const double v_hi = size_t(k) < pb.v_cap.size() ? std::min(pb.lim.v_max, pb.v_cap[size_t(k)]) : pb.lim.v_max;
    const double v_lo = std::max(pb.lim.v_min, v_prev - pb.lim.decel * pb.dt);
    v = std::clamp(v, v_lo, std::max(v_lo, std::min(v_hi, v_prev + pb.lim.accel * pb.dt)));
    double w_lo = std::max(-pb.lim.omega_max, w_prev - pb.lim.alpha * pb.dt);
    double w_hi = std::min(pb.lim.omega_max, w_prev + pb.lim.alpha * pb.dt);
    narrow_to_turn_bounds(pb, k, &w_lo, &w_hi);
    w = std::clamp(w, w_lo, w_hi);
    v_prev = v;
    w_prev = w;
  }
}

namespace {

// Ceres' trust region at the first outer iteration (then carried between
// outer iterations, at least min_trust_radius).
constexpr double kInitialTrustRadius = 1e4;

// The iterates of one solve worth keeping: the cheapest feasible one (the
// start included): when the AL loop ends outside the tolerance (it can
// jump through an obstacle early and not find its way back), a feasible if
// less optimal plan still beats none. And those just outside the
// tolerance, projected at the end when the loop does not converge: the AL
// loop can wander on (a cold start beside an obstacle: the plan returned
// after 20 outer iterations ranged from 0.22 to 0.36 m of progress with
// the iteration budget), and an earlier iterate, projected, can beat the
// last one.
struct Iterates {
  std::vector<double> best_feasible;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<std::pair<double, std::vector<double>>> near_feasible;  // (cost, u)

  void keep(const Problem& pb, const SolverOptions& o, const std::vector<double>& u, const std::vector<double>& g) {
    double violation = 0;
    for (double v : g) violation = std::max(violation, -v);
    if (violation > o.target_violation) {
      if (violation <= o.projection_candidate_violation_m) near_feasible.emplace_back(objective(pb, u.data()), u);
      return;
    }
    const double c = objective(pb, u.data());
    if (c < best_cost) {
      best_cost = c;
      best_feasible = u;
    }
  }
};

// The AL outer loop from res->u with multipliers *lambda and penalty *rho
// (both updated); every iterate goes to *log.
void augmented_lagrangian(const Problem& pb, const SolverOptions& o, SolveResult* res, std::vector<double>* lambda,
                          double* rho, Iterates* log) {
  const int m = pb.num_constraints();
  double trust_radius = kInitialTrustRadius;
  double prev_violation = std::numeric_limits<double>::infinity();
  std::vector<double> states, g;
  evaluate_constraints(pb, res->u.data(), &states, &g);
  log->keep(pb, o, res->u, g);
  for (int outer = 0; outer < o.max_outer_iterations; ++outer) {
    // A budget on the Ceres iterations of one solve bounds its time (the
    // problems that use it up are nearly always infeasible ones, which the
    // planner's fallbacks handle).
    const int budget = o.max_total_iterations - res->iterations;
    if (budget <= 0) break;
    std::vector<ActiveConstraint> active;
    // Rate limits (linear, cheap) are always in: left out, the inner solve
    // chatters between the omega bounds and the next outer iteration starts
    // from a badly violated point. The rate limits at k = 0 are bounds on u_0.
    for (int j = 4; j < pb.num_rate_constraints(); ++j) active.push_back({j, false});
    for (int j = pb.num_rate_constraints(); j < m; ++j)
      if ((*lambda)[j] > 0 || g[j] < o.active_margin_m) active.push_back({j, false});
    std::vector<double> before = res->u;
    res->iterations += run_inner(pb, o, new InnerCost(pb, std::move(active), *lambda, *rho, /*elastic_penalty=*/1.0),
                                 &res->u, o.max_inner_iterations, budget, &trust_radius);
    res->outer_iterations = outer + 1;
    if (!all_finite(res->u)) {
      res->u = before;
      break;
    }
    evaluate_constraints(pb, res->u.data(), &states, &g);
    log->keep(pb, o, res->u, g);
    double violation = 0;
    for (double v : g) violation = std::max(violation, -v);
    // Complementarity: a constraint whose multiplier (from the previous
    // outer iteration) still holds it off its bound has slack g_j while
    // lambda_j / rho > 0. Feasible but not optimal: e.g. from rest an
    // overestimated multiplier on the acceleration chain ramped the speed
    // up at 3/4 of the limit, 32 % costlier. The update below clears it.
    double complementarity = 0;
    for (int j = 0; j < m; ++j)
      if ((*lambda)[j] > 0) complementarity = std::max(complementarity, std::min(g[j], (*lambda)[j] / *rho));
    // Aim below the tolerance: in a D-CBF chain a violation at the tolerance
    // at every step adds up to a visibly cheaper (and less safe) plan.
    if (violation <= o.target_violation && complementarity <= o.complementarity_tolerance_m) break;
    for (int j = 0; j < m; ++j) (*lambda)[j] = std::max(0.0, (*lambda)[j] - *rho * g[j]);
    if (violation > o.violation_shrink * prev_violation) *rho = std::min(*rho * o.penalty_growth, o.penalty_max);
    prev_violation = violation;
  }
}

// The loop ended outside the tolerance: the last iterate and the cheapest
// near-feasible ones, projected onto the constraints; the cheapest
// feasible one (or the best feasible iterate) replaces res->u when cheaper.
void project_iterates(const Problem& pb, const SolverOptions& o, Iterates* log, SolveResult* res) {
  std::stable_sort(log->near_feasible.begin(), log->near_feasible.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::vector<double>> to_project = {res->u};
  for (const auto& nf : log->near_feasible) {
    if (static_cast<int>(to_project.size()) > o.projection_candidates) break;
    if (nf.second != res->u) to_project.push_back(nf.second);
  }
  bool improved = false;
  for (std::vector<double>& projected : to_project) {
    if (!project_onto_constraints(pb, o, &projected)) continue;
    const double projected_cost = objective(pb, projected.data());
    if (log->best_feasible.empty() || projected_cost < log->best_cost) {
      log->best_feasible = projected;
      log->best_cost = projected_cost;
      improved = true;
    }
  }
  if (improved) {
    res->u = log->best_feasible;
    evaluate_result(pb, o, res);
  }
}

// The loop can end just outside the tolerance (a few mm on a D-CBF chain,
// the penalty at its cap) with a plan far cheaper than the best feasible
// iterate, which may be the start itself (standing beside an obstacle).
// The farthest feasible point on the segment between the two (bisection)
// keeps part of that progress.
void segment_search(const Problem& pb, const SolverOptions& o, const std::vector<double>& best_feasible,
                    SolveResult* res) {
  const int n = pb.num_controls();
  const std::vector<double> last = res->u;
  std::vector<double> trial(n);
  auto at = [&](double a) {
    for (int i = 0; i < n; ++i) trial[i] = best_feasible[i] + a * (last[i] - best_feasible[i]);
    return max_violation(pb, trial.data()) <= o.constraint_tolerance;
  };
  double lo = 0.0, hi = 1.0;
  for (int b = 0; b < kSegmentBisections; ++b) {
    const double mid = 0.5 * (lo + hi);
    (at(mid) ? lo : hi) = mid;
  }
  res->u = best_feasible;
  if (lo > 0.0 && at(lo) && objective(pb, trial.data()) < objective(pb, best_feasible.data())) res->u = trial;
  evaluate_result(pb, o, res);
}

}  // namespace

SolveResult CeresMpcSolver::solve(const Problem& pb, const std::vector<double>& warm_u,
                                  const std::vector<double>* warm_multipliers, double warm_penalty) const {
  SolveResult res;
  const int n = pb.num_controls(), m = pb.num_constraints();
  res.u.resize(n);
  for (int i = 0; i < n; ++i) {
    double lo, hi;
    control_bounds(pb, i, &lo, &hi);
    const double w = i < static_cast<int>(warm_u.size()) && std::isfinite(warm_u[i]) ? warm_u[i] : 0.0;
    res.u[i] = std::clamp(w, lo, hi);
  }
  std::vector<double> lambda(m, 0.0);
  double rho = opts_.penalty_initial;
  if (warm_multipliers && static_cast<int>(warm_multipliers->size()) == m) {
    lambda = *warm_multipliers;
    // Bounded: the previous cycle may have ended at a large penalty, which
    // makes the first inner problem stiff; with good multipliers a moderate
    // penalty suffices (the loop raises it again when needed).
    if (warm_penalty > 0) rho = std::clamp(warm_penalty, opts_.penalty_initial, opts_.warm_penalty_max);
  } else if (opts_.estimate_multipliers) {
    estimate_multipliers(pb, res.u, opts_.estimate_margin_m, &lambda);
  }
  Iterates log;
  augmented_lagrangian(pb, opts_, &res, &lambda, &rho, &log);
  res.multipliers = lambda;
  res.penalty = rho;
  evaluate_result(pb, opts_, &res);
  if (!res.feasible && res.finite) project_iterates(pb, opts_, &log, &res);
  if (!res.feasible && !log.best_feasible.empty()) segment_search(pb, opts_, log.best_feasible, &res);
  if (!res.feasible && res.finite) {
    // Repair: the leftover violation is mostly in the (linear) rate limits;
    // clamping the controls onto them moves the states only a little, which
    // may leave every constraint within tolerance.
    SolveResult repaired = res;
    project_controls(pb, &repaired.u);
    evaluate_result(pb, opts_, &repaired);
    if (repaired.feasible) res = repaired;
  }
  return res;
}

bool settled_obstacle(const Problem& pb, const ObstacleTrack& o, const SolverOptions& opts) {
  if (o.x.empty() || o.y.empty()) return false;
  const double speed = std::hypot(o.x.back() - o.x.front(), o.y.back() - o.y.front()) / (pb.N * pb.dt);
  return speed <= opts.relax_max_obstacle_speed_mps && o.age_s >= opts.relax_min_track_age_s;
}

int hold_settled_obstacles(Problem* pb, const SolverOptions& opts) {
  int held = 0;
  for (ObstacleTrack& o : pb->obstacles) {
    // every step slower too: a mover turning round or braking can end the
    // horizon where it began
    if (o.field || o.still_s < opts.hold_still_s ||
        fastest_predicted_speed(o, pb->dt) > opts.relax_max_obstacle_speed_mps)
      continue;
    for (std::vector<double>* v : {&o.x, &o.y, &o.a, &o.b, &o.theta, &o.sigma})
      if (!v->empty()) std::fill(v->begin(), v->end(), v->front());
    ++held;
  }
  return held;
}

std::vector<double> barrier_relaxation(const Problem& pb, const SolverOptions& opts) {
  std::vector<double> relax(pb.num_constraints(), 0.0);
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    const ObstacleTrack& o = pb.obstacles[i];
    if (o.x.empty() || o.y.empty()) continue;
    const int j0 = pb.num_rate_constraints() + static_cast<int>(i) * pb.N;
    const double start[3] = {pb.x0, pb.y0, pb.yaw0};
    const double h0 = barrier_at(pb, o, 0, start).h;
    // Start inside d_safe: h' = h - h(X_0) meets the D-CBF from where it is.
    const double inside = h0 < 0 ? -(1.0 - o.decay) * h0 : 0.0;
    const bool settled = settled_obstacle(pb, o, opts);
    // Nearly static: its predicted ellipses around the current centre.
    ObstacleTrack held;
    if (settled) {
      held = o;
      std::fill(held.x.begin(), held.x.end(), o.x[0]);
      std::fill(held.y.begin(), held.y.end(), o.y[0]);
    }
    double w_prev = 0.0;  // w_k: how far the swelling alone has lowered h at X_0 by step k
    for (int k = 0; k < pb.N; ++k) {
      double swell = 0.0;
      if (settled) {
        const double w = h0 - barrier_at(pb, held, k + 1, start).h;
        swell = w - o.decay * w_prev;  // the D-CBF on h + w_k
        w_prev = w;
      }
      const double r = inside + std::max(0.0, swell);
      if (std::isfinite(r) && r > 0) relax[static_cast<size_t>(j0 + k)] = r;
    }
  }
  return relax;
}

MultiStartResult solve_from_starts(const SolverOptions& opts, const Problem& pb,
                                   std::vector<std::vector<double>> starts, bool least_violating) {
  starts.resize(std::min(starts.size(), static_cast<size_t>(std::max(1, opts.max_total_iterations))));
  MultiStartResult m;
  SolveResult& out = m.best;
  bool out_continues = false;
  int iterations = 0;
  for (size_t s = 0; s < starts.size(); ++s) {
    // split_budget: an equal share of what is left (a start that converges
    // early leaves its iterations to the starts after it); else of all
    SolverOptions shared = opts;
    const int n = static_cast<int>(starts.size());
    const int share = opts.split_budget ? (opts.max_total_iterations - iterations) / (n - static_cast<int>(s))
                                        : opts.max_total_iterations / n;
    shared.max_total_iterations = std::max(1, share);
    SolveResult r = CeresMpcSolver(shared).solve(pb, starts[s]);
    iterations += r.iterations;
    if (!r.finite) continue;
    const double to_beat = out_continues ? opts.recovery_switch_ratio * out.cost : out.cost;
    const bool better =
        !m.found ? (least_violating || r.feasible)
                 : (r.feasible && (!out.feasible || r.cost < to_beat)) ||
                       (least_violating && !r.feasible && !out.feasible && r.max_violation < out.max_violation);
    if (better) {
      out = r;
      m.found = true;
      out_continues = s == 0;
    }
  }
  out.iterations = iterations;
  return m;
}

SolveResult CeresMpcSolver::solve_elastic(const Problem& pb_in, const std::vector<double>& start_u,
                                          const std::vector<double>* relax) const {
  // Some obstacles ask more than any plan can give: from inside d_safe
  // (h(X_0) < 0) the constraint h(X_{k+1}) >= (1 - gamma) h(X_k) asks h to
  // grow by gamma |h| at once, which a robot at rest or facing the obstacle
  // cannot do; and the predicted ellipse of a static obstacle swells with
  // its uncertainty, which can make h fall faster than a robot that must
  // turn first can get away (a robot that only stops would then stay where
  // it is, since standing misses the hard constraints every cycle). The
  // relaxed problem (barrier_relaxation) applies the D-CBF to the obstacle
  // as it is now: its swelling excused, and h measured from where it
  // starts when that is inside d_safe. The cost then takes the robot out
  // and around.
  Problem pb = pb_in;
  pb.relax = relax ? *relax : barrier_relaxation(pb_in, opts_);
  pb.relax.resize(static_cast<size_t>(pb.num_constraints()), 0.0);  // constraints added since: not relaxed
  // Starts: the given one, braking (zero controls projected onto the rate
  // limits), and a turn on the spot to either side followed by driving off;
  // braking alone would leave the robot standing (feasible, as h stays
  // where standing keeps it, but never out). The cheapest feasible plan
  // wins, else the least violating one.
  std::vector<std::vector<double>> starts = {start_u, std::vector<double>(pb.num_controls(), 0.0)};
  for (double side : {1.0, -1.0}) {
    std::vector<double> guess(pb.num_controls());
    for (int k = 0; k < pb.N; ++k) {
      const bool turning = k < pb.N / 2;
      guess[2 * k] = turning ? 0.0 : pb.lim.v_max;
      guess[2 * k + 1] = turning ? side * pb.lim.omega_max : 0.0;
    }
    starts.push_back(guess);
  }
  for (std::vector<double>& u : starts) project_controls(pb, &u);
  SolveResult out = solve_from_starts(opts_, pb, std::move(starts), /*least_violating=*/true).best;
  const bool shifted_feasible = out.feasible;
  // report against the original constraints
  evaluate_result(pb_in, opts_, &out);
  out.feasible = shifted_feasible;  // feasible for the shifted barrier
  return out;
}

}  // namespace evade::planning
