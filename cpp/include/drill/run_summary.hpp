// The summary of one run (summary.json of `drillsim --job run` and of `drillpy simulate`): the one
// definition of its keys, their order and their units. drillsim writes it with the configuration
// and the job; drillpy's bindings expose it as RunReport.summary().
#pragma once

#include <cmath>

#include "drill/config.hpp"
#include "drill/simulation.hpp"

namespace drill {

/// Keys, in the order drillpy writes them (drillsim's json sorts them): SS (Eq. 3.4,
/// dimensionless; null when undefined), mean top speed [rad/s], stick fraction (null when
/// undefined), complete stick and slip phase durations [s], the period in stick-slip cycles (0: no
/// periodic regime) and the stick and slip durations of the last period [s]; with the axial-torsional
// model (axial.type = rgd) also the WOB and rate of penetration (mean and standard deviation), the
// bit-bounce fraction, the mean depth of cut, the mechanical specific energy and RGD's steady drilling
// at the operating point.
template <class Json = nlohmann::ordered_json>
Json run_summary(const RunReport& r) {
  auto finite_or_null = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
  Json s = Json::object();
  s["severity"] = finite_or_null(r.severity);
  s["mean_top_speed_rad_s"] = r.mean_top_speed;
  s["stick_fraction"] = finite_or_null(r.stick_fraction);
  s["stick_durations_s"] = r.stick;
  s["slip_durations_s"] = r.slip;
  s["period_cycles"] = r.periodic.period_cycles;
  s["period_stick_s"] = r.periodic.stick;
  s["period_slip_s"] = r.periodic.slip;
  if (r.axial.present()) {  // the axial-torsional model (axial.type = rgd): its axial metrics after the transient
    const AxialReport& a = r.axial;
    s["mean_wob_n"] = finite_or_null(a.mean_wob);
    s["wob_std_n"] = finite_or_null(a.wob_std);
    s["mean_rop_m_s"] = finite_or_null(a.mean_rop);
    s["rop_std_m_s"] = finite_or_null(a.rop_std);
    s["bounce_fraction"] = finite_or_null(a.bounce_fraction);
    s["mean_depth_of_cut_m"] = finite_or_null(a.mean_depth_of_cut);
    s["mse_pa"] = finite_or_null(a.mse);
    s["steady_wob_n"] = a.steady_wob;
    s["steady_rop_m_s"] = a.steady_rop;
    s["steady_depth_of_cut_m"] = a.steady_depth;
    s["steady_torque_nm"] = a.steady_torque;
    s["steady_mse_pa"] = a.steady_mse;
    s["steady_speed_rad_s"] = finite_or_null(a.steady_speed);  // null: the drive cannot carry steady drilling
  }
  return s;
}

}  // namespace drill
