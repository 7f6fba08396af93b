// Built-in configurations of the thesis's three systems.
//  * thesis-field  Table 3.1 string (Ritto et al. 2017), 100 elements (91 DP + 9 BHA), modal damping
//                  0.095 / 0.02, hysteretic law of section 3.2 (beta1 = 0.14), dt = 0.512 ms.
//  * thesis-ch4    chapter 4's deterministic model (Fig. 4.8): the thesis-field string at WOB = 200 kN
//                  (section 3.3's example; chapter 4 does not state its WOB) with all 100 modes kept:
//                  SS > 0.5 below 15.98 +- 0.02 rad/s, the thesis's 16 (docs/presets.md has the evidence).
//  * thesis-rig    Table 5.1 test rig: 1.7 m steel bar of radius 2.5 mm with the 3.921 kg disk of
//                  radius 0.069 m lumped at the bit (0.5 m r^2 = 9.33e-3 kg m^2); first mode 2.89 Hz;
//                  law and damping identified on sample 175 (docs/presets.md).
//  * thesis-ch6    section 6.6: 1700 m DP + 300 m BHA (Table 3.1 cross sections), 100 elements each,
//                  Rayleigh damping 0.05 at 1 Hz and 0.01 at 10 Hz, 25 fixed-interface modes each.
//  * rgd-field     axial-torsional (docs/axial.md): a 2000 m string (1700 m DP + 300 m BHA, Table 3.1 cross
//                  sections, 100 elements) with 20 torsional and 10 axial modes, the Richard-Germay-
//                  Detournay bit with the parameter set of Richard, Germay & Detournay (J. Sound Vib. 2007)
//                  as issue 34 quotes it: a = 0.108 m, eps = sigma = 60 MPa, zeta = 0.6, l = 11 mm,
//                  gamma = 1, mu = 0.6, N = 4 (not checked against the paper by this session); hook load
//                  with 150 kN on bit at 4 rad/s (38 RPM; operating point chosen here, not the paper's),
//                  where steady drilling is unstable and grows into stick-slip (docs/axial.md).
//  * rgd-rig       the test rig, axial-torsional (docs/axial.md, "The rgd-rig preset"): thesis-rig's bar and
//                  disk, the rig's open-loop motor (8 N m at stall and 300 RPM: c_m 0.25, section 5.1;
//                  J_m 0.0186 kg m^2 and the 17.27 rad/s command calibrated on sample 175), the law of
//                  Eq. (5.1) identified on sample 175 (0-20 s) on the axial WOB, damping 0.03, and an RGD
//                  cut of the 12 mm masonry bit (a 6 mm, N 2, eps = sigma 30 MPa: the concrete's 30 fck,
//                  zeta 0.6, l 2.3 mm) under the rig's jack: a 2 mm/s feed (section 5.2) relaxing to the
//                  565 N set force in 0.1 s.
#pragma once

#include <string>
#include <vector>

#include "drill/config.hpp"

namespace drill {

inline std::vector<std::string> preset_names() {
  return {"thesis-field", "thesis-ch4", "thesis-rig", "thesis-ch6", "rgd-field", "rgd-rig"};
}

inline json thesis_hysteretic_law_json(double beta1) {
  // Section 3.2 parameters; the bit speed unit is RPM (docs/units.md gives the evidence).
  return {{"type", "hysteretic"}, {"speed_unit", "rpm"}, {"wob_ref_n", 245e3}, {"b0", 3478.0}, {"b1", 938.0},
          {"b2", 2.56},          {"b3", 0.38},          {"b4", 0.78},         {"b5", 1.1},     {"beta1", beta1},
          {"beta2", 10.6}};
}

inline json table31_section(const std::string& name, double length, int elements) {
  const bool dp = name == "DP";
  return {{"name", name},
          {"length_m", length},
          {"outer_radius_m", dp ? 0.070 : 0.0803},
          {"inner_radius_m", dp ? 0.0595 : 0.0363},
          {"youngs_modulus_pa", 220e9},
          {"poisson_ratio", 0.29},
          {"density_kg_m3", 7800.0},
          {"elements", elements}};
}

inline json preset_json(const std::string& name) {
  std::vector<double> speeds, wobs;
  for (int k = 0; k < 22; ++k) speeds.push_back(6.0 + k);              // B = [6, 27] rad/s
  for (int k = 0; k < 12; ++k) wobs.push_back(22e3 + k * 245e3 / 11);  // 22 ... 267 kN
  if (name == "thesis-field") {
    return {{"name", name},
            {"description", "Table 3.1 field string (thesis chapters 3-4)"},
            {"string", {{"sections", {table31_section("DP", 4733.60, 91), table31_section("BHA", 466.45, 9)}}}},
            {"rom", {{"modes", 20}}},
            {"damping", {{"type", "modal"}, {"ratios", {0.095, 0.02}}}},
            {"law", thesis_hysteretic_law_json(0.14)},
            {"operation", {{"top_speed_rad_s", 16.0}, {"wob_n", 245e3}}},
            {"simulation",
             {{"scheme", "modified_euler"}, {"dt_s", 5.12e-4}, {"duration_s", 200.0}, {"transient_s", 100.0},
              {"output_stride", 20}}},
            {"sweep", {{"top_speeds_rad_s", speeds}, {"wobs_n", wobs}}}};
  }
  if (name == "thesis-ch4") {
    json j = preset_json("thesis-field");
    j["name"] = name;
    j["description"] = "Chapter 4 deterministic model: Table 3.1 string at WOB = 200 kN, 100 modes (Fig. 4.8)";
    j["rom"]["modes"] = 100;
    j["operation"]["wob_n"] = 200e3;
    return j;
  }
  if (name == "thesis-rig") {
    // Law: Eq. (5.3) identified on test-rig sample 175 (0-40 s) by `drillpy analyze` (least squares
    // on the slip phases, bit speed in RPM); modal damping ratio 0.25: the effective value whose
    // simulation at the constant mean top speed (80.9 RPM) matches the measured stick-slip best.
    // Provenance and the numbers it replaced: docs/presets.md.
    return {{"name", name},
            {"description", "Table 5.1 laboratory test rig (thesis chapter 5)"},
            {"string",
             {{"sections",
               {{{"name", "bar"},
                 {"length_m", 1.7},
                 {"outer_radius_m", 0.0025},
                 {"inner_radius_m", 0.0},
                 {"youngs_modulus_pa", 220e9},
                 {"poisson_ratio", 0.29},
                 {"density_kg_m3", 7800.0},
                 {"elements", 20}}}},
              {"lumped_inertias", {{{"node", -1}, {"inertia_kg_m2", 0.5 * 3.921 * 0.069 * 0.069}}}}}},
            {"rom", {{"modes", 1}}},
            {"damping", {{"type", "modal"}, {"ratios", {0.25}}}},
            {"law",
             {{"type", "polynomial_hysteretic"},
              {"speed_unit", "rpm"},
              {"wob_ref_n", 557.1},
              {"a0", 0.0},
              {"a1", 2.187},
              {"a2", 1.976},
              {"a3", 0.0},
              {"a4", 1.983},
              {"a5", -1.315e-3},
              {"a6", -4.823e-5},
              {"a7", 1.047e-7},
              {"ref_speed", 90.36},
              {"gain", 1.36},
              {"beta1", 0.08625},
              {"beta2", 0.0052}}},
            {"operation", {{"top_speed_rad_s", 80.9 * M_PI / 30.0}, {"wob_n", 557.1}}},
            {"simulation",
             {{"scheme", "modified_euler"}, {"dt_s", 1e-4}, {"duration_s", 40.0}, {"transient_s", 5.0},
              {"output_stride", 10}}},
            {"metrics", {{"stick_threshold_fraction", 0.05}, {"stick_debounce_s", 0.005}}}};
  }
  if (name == "thesis-ch6") {
    return {{"name", name},
            {"description", "Section 6.6 string: 1700 m DP + 300 m BHA, Craig-Bampton substructures"},
            {"string", {{"sections", {table31_section("DP", 1700.0, 100), table31_section("BHA", 300.0, 100)}}}},
            {"rom", {{"modes", 50}}},
            {"damping", {{"type", "rayleigh"}, {"pairs", {{1.0, 0.05}, {10.0, 0.01}}}}},
            {"law", thesis_hysteretic_law_json(0.14)},
            {"operation", {{"top_speed_rad_s", 16.0}, {"wob_n", 245e3}}},
            {"simulation",
             {{"scheme", "modified_euler"}, {"dt_s", 2e-4}, {"duration_s", 200.0}, {"transient_s", 100.0},
              {"output_stride", 50}}},
            {"sweep", {{"top_speeds_rad_s", speeds}}},
            {"craig_bampton", {{"modes", {25, 25}}}}};
  }
  if (name == "rgd-field") {
    return {{"name", name},
            {"description", "axial-torsional 2000 m string with the Richard-Germay-Detournay bit (docs/axial.md)"},
            {"string", {{"sections", {table31_section("DP", 1700.0, 85), table31_section("BHA", 300.0, 15)}}}},
            {"rom", {{"modes", 20}}},
            {"damping", {{"type", "modal"}, {"ratios", {0.095, 0.02}}}},
            {"operation", {{"top_speed_rad_s", 4.0}, {"wob_n", 150e3}}},
            {"axial",
             {{"type", "rgd"},
              {"top", "hook_load"},
              {"modes", 10},
              {"damping_ratio", 0.05},
              {"bit",
               {{"radius_m", 0.108},
                {"specific_energy_pa", 60e6},
                {"contact_strength_pa", 60e6},
                {"zeta", 0.6},
                {"wear_flat_m", 0.011},
                {"gamma", 1.0},
                {"mu", 0.6},
                {"blades", 4}}}}},
            {"simulation",
             {{"scheme", "modified_euler"}, {"dt_s", 5e-4}, {"duration_s", 60.0}, {"transient_s", 30.0},
              {"output_stride", 20}, {"start", "steady"}}}};
  }
  if (name == "rgd-rig") {
    // The test rig with its axial side (docs/axial.md, "The rgd-rig preset"; benchmarks/axial_rig_wob.py):
    // thesis-rig's string; the motor's rating (c_m = 8 N m / 31.4 rad/s, T_max 8 N m, section 5.1) and the
    // inertia and command `drillpy analyze --calibrate 0:20` finds on sample 175; Eq. (5.1) as that
    // command identifies it (0-20 s); the whole-rig calibration's damping ratio (0.030-0.033). The bit:
    // sample 175's 12 mm masonry bit (two cutting edges, an assumption), eps = sigma = the concrete's
    // 30 MPa (30 fck, section 5.2), RGD's zeta, gamma, mu, and the wear flat that puts steady drilling's
    // WOB at the 565 N set force. The jack: the design's 2 mm/s (section 5.2), kappa = 1 / (tau k) with
    // tau 0.1 s (the rig model's jack relaxation) and k = 2.0e5 N/m (the bar's E A / L in series with the
    // cut's N a zeta eps). One axial mode: the disk's 3.31 kg on the bar, 140 Hz.
    json c = preset_json("thesis-rig");
    c["name"] = name;
    c["description"] = "Table 5.1 test rig with its motor, jack and an RGD cut: axial-torsional (docs/axial.md)";
    c["damping"] = {{"type", "modal"}, {"ratios", {0.03}}};
    c["law"] = {{"type", "polynomial"}, {"speed_unit", "rpm"}, {"wob_ref_n", 562.9}, {"a0", 2.0906}, {"a1", -0.17888},
                {"a2", 1.92968}, {"a3", 0.0}, {"a4", 1.94462}, {"a5", -3.1835e-3}, {"a6", -3.0877e-5},
                {"a7", 1.0397e-7}, {"ref_speed", 89.96}, {"gain", 1.36}};
    c["top_drive"] = {{"type", "motor"}, {"slope_nms_rad", 0.25}, {"inertia_kg_m2", 0.0186}, {"max_torque_nm", 8.0}};
    c["operation"] = {{"top_speed_rad_s", 17.27}, {"wob_n", 565.0}};
    c["axial"] = {{"type", "rgd"},
                  {"top", "jack"},
                  {"rop_m_s", 2e-3},
                  {"jack_admittance_m_s_n", 5e-5},
                  {"torque", "law"},
                  {"modes", 1},
                  {"damping_ratio", 0.05},
                  {"bit_mass_kg", 7800.0 * M_PI * 0.069 * 0.069 * 0.0284},
                  {"bit",
                   {{"radius_m", 0.006},
                    {"specific_energy_pa", 30e6},
                    {"contact_strength_pa", 30e6},
                    {"zeta", 0.6},
                    {"wear_flat_m", 2.3e-3},
                    {"gamma", 1.0},
                    {"mu", 0.6},
                    {"blades", 2}}}};
    c["simulation"]["start"] = "steady";
    return c;
  }
  std::string known;
  for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("preset = \"" + name + "\": unknown preset (known: " + known + ")");
}

inline Config preset(const std::string& name) { return parse_config(preset_json(name)); }

}  // namespace drill
