#include "prediction/params.h"

namespace evade::prediction {

PredictorParams PredictorParams::from_config(const config::Node& s) {
  PredictorParams p;
  p.prediction_steps = s.get_int("prediction_steps", 1, 1000);
  p.prediction_dt_s = s.get_double("prediction_dt_s", 1e-3, 10.0);
  p.max_frame_gap_s = s.get_double("max_frame_gap_s", 1e-3, 60.0);
  p.coast_max_s = s.get_double("coast_max_s", 0.0, 60.0);
  p.coast_min_frames = s.get_int("coast_min_frames", 1, 1000);
  p.max_abs_coordinate_m = s.get_positive("max_abs_coordinate_m");
  p.max_axis_m = s.get_positive("max_axis_m");

  const config::Node f = s.section("filter");
  p.filter.init_speed_std_mps = f.get_positive("init_speed_std_mps");
  p.filter.init_accel_std_mps2 = f.get_positive("init_accel_std_mps2");
  p.filter.jerk_psd_m2ps5 = f.get_positive("jerk_psd_m2ps5");
  p.filter.axis_psd_m2ps = f.get_positive("axis_psd_m2ps");
  p.filter.theta_psd_rad2ps = f.get_positive("theta_psd_rad2ps");
  p.filter.r_axis_m2 = f.get_positive("r_axis_m2");
  p.filter.r_theta_rad2 = f.get_positive("r_theta_rad2");
  p.filter.orientation_min_elongation_m = f.get_positive("orientation_min_elongation_m");
  f.close();

  const config::Node mv = s.section("maneuver");
  p.maneuver.enabled = mv.get<bool>("enabled");
  p.maneuver.jerk_psd_m2ps5 = mv.get_positive("jerk_psd_m2ps5");
  p.maneuver.mean_quiet_s = mv.get_positive("mean_quiet_s");
  p.maneuver.mean_maneuver_s = mv.get_positive("mean_maneuver_s");
  p.maneuver.model = mv.get_choice("model", {"ca", "cv"});
  p.maneuver.accel_psd_m2ps3 = mv.get_positive("accel_psd_m2ps3");
  mv.close();

  const config::Node st = s.section("stationary");
  p.stationary.enabled = st.get<bool>("enabled");
  p.stationary.mean_stationary_s = st.get_positive("mean_stationary_s");
  p.stationary.stop_share = st.get_double("stop_share", 0.0, 1.0);
  p.stationary.position_psd_m2ps = st.get_positive("position_psd_m2ps");
  if (p.stationary.enabled && !p.maneuver.enabled)
    st.fail("enabled", "the stationary mode needs maneuver.enabled (a start from rest is a manoeuvre)");
  st.close();

  const config::Node fr = s.section("fragment");
  p.fragment.enabled = fr.get<bool>("enabled");
  p.fragment.min_parent_speed_mps = fr.get_double("min_parent_speed_mps", 0.0, 100.0);
  p.fragment.margin_m = fr.get_double("margin_m", 0.0, 10.0);
  p.fragment.extra_speed_std_mps = fr.get_double("extra_speed_std_mps", 0.0, 100.0);
  fr.close();

  const config::Node a = s.section("adaptive_noise");
  p.adaptive.window_frames = a.get_int("window_frames", 2, 1000);
  p.adaptive.shape_variation_source = a.get_choice("shape_variation_source", {"own", "tracker"});
  p.adaptive.kappa = a.get_positive("kappa");
  p.adaptive.gamma = a.get_positive("gamma");
  p.adaptive.xi_min_m2 = a.get_positive("xi_min_m2");
  p.adaptive.xi_max_m2 = a.get_positive("xi_max_m2");
  if (p.adaptive.xi_max_m2 <= p.adaptive.xi_min_m2) a.fail("xi_max_m2", "must be greater than xi_min_m2");
  p.adaptive.r_pos_min_m2 = a.get_positive("r_pos_min_m2");
  p.adaptive.r_pos_max_m2 = a.get_positive("r_pos_max_m2");
  if (p.adaptive.r_pos_max_m2 < p.adaptive.r_pos_min_m2) a.fail("r_pos_max_m2", "must be at least r_pos_min_m2");
  a.close();

  const config::Node u = s.section("uncertainty");
  p.uncertainty.confidence = u.get_double("confidence", 0.5, 0.999999);
  p.uncertainty.min_axis_m = u.get_positive("min_axis_m");
  p.uncertainty.root_tolerance_m = u.get_double("root_tolerance_m", 1e-15, 1e-3);
  p.uncertainty.max_inflation_m = u.get_double("max_inflation_m", 0.0, 100.0);
  u.close();

  const config::Node l = s.section("limits");
  p.limits.max_speed_mps = l.get_positive("max_speed_mps");
  p.limits.max_accel_mps2 = l.get_positive("max_accel_mps2");
  p.limits.max_accel_time_s = l.get_double("max_accel_time_s", 0.0, 1e3);
  l.close();

  s.close();
  return p;
}

}  // namespace evade::prediction
