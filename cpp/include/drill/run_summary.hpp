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
/// periodic regime) and the stick and slip durations of the last period [s].
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
  return s;
}

}  // namespace drill
