#include "metrics/ellipse_calibration.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace evade::metrics {

const char* class_name(ObjectClass c) {
  switch (c) {
    case ObjectClass::kWalker:
      return "walker";
    case ObjectClass::kBike:
      return "bike";
    case ObjectClass::kBall:
      return "ball";
    case ObjectClass::kDog:
      return "dog";
    case ObjectClass::kStatic:
      return "static";
    case ObjectClass::kOther:
      break;
  }
  return "other";
}

ObjectClass classify(const evade::sim_obstacle_t& o, bool still) {
  if (still) return ObjectClass::kStatic;
  if (o.shape == "box") return std::max(o.length, o.width) <= 2.5 ? ObjectClass::kBike : ObjectClass::kOther;
  if (o.height >= 1.0) return ObjectClass::kWalker;
  if (o.radius <= 0.12 && o.height <= 2.5 * o.radius) return ObjectClass::kBall;
  return ObjectClass::kDog;
}

const char* age_bin_name(int bin) {
  static const char* const kNames[kAgeBins] = {"0-0.5", "0.5-1", "1-2", "2-5", "5+"};
  return kNames[bin];
}

int age_bin(double age_s) {
  int bin = 0;
  while (bin + 1 < kAgeBins && age_s >= kAgeBinStart[static_cast<size_t>(bin + 1)]) ++bin;
  return bin;
}

namespace {

// p in the ellipse's own frame.
Vec2 to_ellipse(Vec2 p, Vec2 c, double theta) {
  const double dx = p.x - c.x, dy = p.y - c.y, co = std::cos(theta), si = std::sin(theta);
  return {co * dx + si * dy, -si * dx + co * dy};
}

bool inside(Vec2 q, double a, double b) { return (q.x / a) * (q.x / a) + (q.y / b) * (q.y / b) <= 1.0; }

// Distance from q (inside) to the ellipse's boundary, from 360 boundary points
// (over-estimates by at most about a * (pi / 360)^2 / 2).
double boundary_distance(Vec2 q, double a, double b) {
  double best = 1e300;
  for (int i = 0; i < 360; ++i) {
    const double t = i * M_PI / 180.0;
    best = std::min(best, std::hypot(a * std::cos(t) - q.x, b * std::sin(t) - q.y));
  }
  return best;
}

double body_radius(const TrueObject& o) {
  return o.radius > 0.0 ? o.radius : 0.5 * std::sqrt(o.box.length * o.box.width);
}

void add_step(EllipseStep* s, bool in, bool inflation_in, bool body_in, double area, double sigma, double error) {
  ++s->n;
  s->inside += in;
  s->inflation_inside += inflation_in;
  s->body_inside += body_in;
  s->area_sum_m2 += area;
  s->sigma_sum_m += sigma;
  s->error_sum_m += error;
}

}  // namespace

bool body_inside_ellipse(const TrueObject& body, Vec2 c, double a, double b, double theta) {
  if (body.radius > 0.0) {
    const Vec2 q = to_ellipse(body.centre, c, theta);
    return inside(q, a, b) && boundary_distance(q, a, b) >= body.radius;
  }
  for (const Vec2& corner : body.box.corners())
    if (!inside(to_ellipse(corner, c, theta), a, b)) return false;
  return true;
}

void add_calibration(const evade::track_prediction_t& tp, const std::vector<TrueObject>& truth, ObjectClass cls,
                     double age_s, double min_track_age_s, EllipseCalibration* cal) {
  const bool old = age_s >= min_track_age_s;
  EllipseTally* by_class = old ? &cal->by_class[static_cast<size_t>(cls)] : nullptr;
  EllipseTally* by_age = &cal->by_age[static_cast<size_t>(age_bin(age_s))];
  const size_t n = std::min(truth.size(), static_cast<size_t>(std::max(tp.horizon, 0)));
  for (EllipseTally* t : {by_class, by_age}) {
    if (!t || n == 0) continue;
    if (t->steps.size() < n) t->steps.resize(n);
    ++t->predictions;
    t->excess_sum_m +=
        std::sqrt(std::max(0.0, (tp.a[0] - tp.sigma[0]) * (tp.b[0] - tp.sigma[0]))) - body_radius(truth[0]);
  }
  for (size_t k = 0; k < n; ++k) {
    const Vec2 c{tp.x[k], tp.y[k]};
    const bool in = inside(to_ellipse(truth[k].centre, c, tp.theta[k]), tp.a[k], tp.b[k]);
    const double error = std::hypot(truth[k].centre.x - c.x, truth[k].centre.y - c.y);
    const bool inflation_in = error <= tp.sigma[k];
    const bool body_in = body_inside_ellipse(truth[k], c, tp.a[k], tp.b[k], tp.theta[k]);
    const double area = M_PI * tp.a[k] * tp.b[k];
    for (EllipseTally* t : {by_class, by_age})
      if (t) add_step(&t->steps[k], in, inflation_in, body_in, area, tp.sigma[k], error);
  }
}

namespace {

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

template <typename F>
std::string per_step(const EllipseTally& t, F f) {
  std::string out = "[";
  for (size_t k = 0; k < t.steps.size(); ++k) {
    const EllipseStep& s = t.steps[k];
    out += (k ? ", " : "") + (s.n ? number(f(s)) : std::string("null"));
  }
  return out + "]";
}

// {"name": [per step], ...} over the tallies that have predictions.
template <size_t N, typename Name, typename F>
std::string object(const std::array<EllipseTally, N>& tallies, Name name, F f) {
  std::string out = "{";
  bool first = true;
  for (size_t i = 0; i < N; ++i) {
    if (tallies[i].predictions == 0) continue;
    out += std::string(first ? "" : ", ") + "\"" + name(static_cast<int>(i)) + "\": " + f(tallies[i]);
    first = false;
  }
  return out + "}";
}

template <size_t N, typename Name>
std::string members(const std::string& prefix, const std::array<EllipseTally, N>& t, Name name) {
  auto steps = [&](auto f) { return object(t, name, [&](const EllipseTally& x) { return per_step(x, f); }); };
  std::string o;
  o += "  \"" + prefix + "_n\": " + steps([](const EllipseStep& s) { return double(s.n); }) + ",\n";
  o += "  \"" + prefix + "_coverage\": " + steps([](const EllipseStep& s) { return double(s.inside) / s.n; }) + ",\n";
  o += "  \"" + prefix +
       "_inflation_coverage\": " + steps([](const EllipseStep& s) { return double(s.inflation_inside) / s.n; }) + ",\n";
  o += "  \"" + prefix +
       "_body_coverage\": " + steps([](const EllipseStep& s) { return double(s.body_inside) / s.n; }) + ",\n";
  o += "  \"" + prefix + "_area_m2\": " + steps([](const EllipseStep& s) { return s.area_sum_m2 / s.n; }) + ",\n";
  o += "  \"" + prefix + "_inflation_m\": " + steps([](const EllipseStep& s) { return s.sigma_sum_m / s.n; }) + ",\n";
  o += "  \"" + prefix + "_error_m\": " + steps([](const EllipseStep& s) { return s.error_sum_m / s.n; }) + ",\n";
  o += "  \"" + prefix + "_extent_excess_m\": " + object(t, name, [](const EllipseTally& x) {
         return number(x.excess_sum_m / x.predictions);
       });
  return o;
}

}  // namespace

std::string calibration_json(const EllipseCalibration& cal) {
  auto cls = [](int i) { return std::string(class_name(static_cast<ObjectClass>(i))); };
  auto age = [](int i) { return std::string(age_bin_name(i)); };
  return members("class", cal.by_class, cls) + ",\n" + members("age", cal.by_age, age);
}

}  // namespace evade::metrics
