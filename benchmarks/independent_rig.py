"""An independent simulator of the thesis test rig (chapter 5, Table 5.1) for checking ``drillpy loop``.

It shares no code with drillpy (NumPy and SciPy only; drillpy is not imported) and differs from
drillpy's engine on purpose, the way an outside reviewer's rig model would:

* **String**: a solid steel bar, L = 1.7 m, radius 2.5 mm (J_p = pi r^4 / 2 = 6.14e-11 m^4), density
  7850 kg/m^3, G chosen so that G J_p / L = 3.08 N m/rad (G = 85.3 GPa, i.e. E = 220 GPa with
  Poisson 0.29). It is cut into ``N_SEG`` = 8 equal torsional springs k_s = N G J_p / L with the
  segments' rotary inertia lumped at the nodes (half a segment at each end; finite differences,
  every degree of freedom kept). Node 0 is the top (driven), node N the bit, which carries the disk
  J_b = 9.33e-3 kg m^2 (drillpy: 20 linear finite elements reduced to one mode).
* **Damping**: modal, zeta = 0.03 on every mode of the top-clamped string (C = M Phi diag(2 zeta
  omega_i) Phi^T M, Phi mass-normalized), acting on the velocities relative to the top's rigid
  rotation (a rigid rotation is not damped); its reaction goes to the top.
* **Bit-rock law** (Tucker-Wang form, Eq. 3.1), v the bit speed [rad/s]:

      T_law(v, W) = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)] W / W_ref

  c0 = 1.2 N m, alpha0 = 20 s/rad, alpha1 = 0.826 s/rad, alpha2 = 0.103 s^2/rad^2, W_ref = 557.1 N:
  2.74 N m at its low-speed maximum (3.1 rad/s), 2.2 N m at 8.47 rad/s with a slope of -0.09 N m s/rad
  there (the slope of the thesis's Eq. 5.1 fit at that speed), 1.67 N m at 20 rad/s. At 8.47 rad/s
  and 557 N the clean rig stick-slips with SS about 1.16, stick fraction 0.15, 2.6-2.7 Hz, the
  torque between 1.0 and 2.7 N m (5-95 %).
* **Stick**: a true set-valued stick. When the bit speed reaches or crosses zero while the torque
  the string applies to the bit, |T_str|, is within the static capacity T_s + T_sf, the bit is held
  at zero speed; it breaks away when |T_str| exceeds that capacity. For the plain law T_s is the
  law's low-speed maximum (times W_law / W_ref). While stuck the load cell reads the part of T_str
  the contact carries (up to T_s; a string friction takes the rest).
* **Top**: prescribed speed Omega = 8.47 rad/s (the top node's angle integrates it), or, with
  ``top_drive_dynamics``, an inertia J_m driven by an open-loop motor.
* **Integration**: semi-implicit (symplectic) Euler, fixed step ``DT`` = 2e-5 s (the highest
  string mode is about 3.1e4 rad/s, omega dt = 0.62); the bit's acceleration is solved implicitly
  (safeguarded Newton) when the law depends on it (hysteresis). 5 s of settling from rest (bit
  stuck, string untwisted) precede the record.
* **Record**: 40 s at 500 Hz, channels time_s, bit_speed_rad_s, top_speed_rad_s, torque_on_bit_Nm
  (the contact torque of the law, as a load cell between bit and rock reads it) and wob_N.
* **WOB**: W(t) = W_0 (1 + 0.14 z(t)), W_0 = 557.1 N, z unit-variance Gaussian noise low-passed at
  2 Hz (4th-order Butterworth, zero phase). The recorded WOB always fluctuates; the law uses the
  constant W_0 unless ``wob_coupling``.
* **Noise**: white, 0.05 rad/s on both speeds, 0.02 N m on the torque, 2 N on the WOB, times
  ``--noise``.

Injectable effects (``--effects a,b``; ``--size full|half``; parameters in SI):

================== ================================================= ===================
effect             model change                                      full / half
================== ================================================= ===================
bit_hysteresis     T = T_law (1 + beta1 tanh(beta2 a) sign(v)) (3.3)  beta1 0.2 / 0.1,
                   a the bit acceleration [rad/s^2]                   beta2 0.05 s^2/rad
wob_coupling       law at W_eff = W_0 (1 + k (W(t)/W_0 - 1))          k 1 / 0.5
top_drive_dynamics J_m Omega' = c_m (Omega_c - Omega) - T_top;       c_m 0.25 / 0.5 N m s/rad,
                   Omega_c = 8.47 + T_law(8.47)/c_m                   J_m 0.02 kg m^2
sensor_lag         every channel through a causal 2nd-order          f_c 10 / 20 Hz
                   Butterworth low-pass (scipy.signal.lfilter)
static_friction    break-away torque T_s (above the law's maximum)    4.5 / 3.62 N m
string_friction    Coulomb T_sf sign(v) on the bit, not measured      0.3 / 0.15 N m
string_stiffness   the bar's GJ times a factor                        0.85 / 0.925
viscous_damping    c_v v on the bit, not measured                     0.03 / 0.015 N m s/rad
top_speed_ramp     commanded top speed ramps linearly over the        +15 % / +7.5 %
                   record (outside the loop's catalogue)
================== ================================================= ===================

(The half static torque is half-way between the law's maximum, 2.74 N m, and 4.5 N m: 3.62 N m.)

    python3 benchmarks/independent_rig.py --effects static_friction,wob_coupling --size full \\
        --seed 3 --noise 1 --out rec.csv
    python3 benchmarks/independent_rig.py --summary        # a clean record's SS, stick fraction, frequency
    python3 benchmarks/independent_rig.py --summary --law eq51   # the control: the declared preset's own Eq. (5.1)
"""
from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np
import scipy.linalg
import scipy.signal

# ------------------------------------------------------------------------------------- the rig
LENGTH_M = 1.7
RADIUS_M = 2.5e-3
DENSITY = 7850.0
GJ_OVER_L = 3.08                      # N m/rad
J_P = math.pi * RADIUS_M ** 4 / 2     # m^4
G_PA = GJ_OVER_L * LENGTH_M / J_P     # ~85.3e9 Pa
J_BIT = 9.33e-3                       # kg m^2
N_SEG = 8
ZETA = 0.03
OMEGA0 = 8.47                         # rad/s
W0 = 557.1                            # N
W_REF = 557.1                         # N
WOB_STD = 0.14                        # relative
WOB_BAND_HZ = 2.0
NOISE = {"bit_speed": 0.05, "top_speed": 0.05, "torque_on_bit": 0.02, "wob": 2.0}

# Tucker-Wang law (Eq. 3.1), rad/s units
C0, ALPHA0, ALPHA1, ALPHA2 = 1.2, 20.0, 0.826, 0.103

DT = 2e-5
FS_HZ = 500.0
DURATION_S = 40.0
SETTLE_S = 5.0

EFFECTS = {
    "bit_hysteresis": {"full": {"beta1": 0.2, "beta2": 0.05}, "half": {"beta1": 0.1, "beta2": 0.05}},
    "wob_coupling": {"full": {"k": 1.0}, "half": {"k": 0.5}},
    "top_drive_dynamics": {"full": {"c_m": 0.25, "J_m": 0.02}, "half": {"c_m": 0.5, "J_m": 0.02}},
    "sensor_lag": {"full": {"f_c": 10.0}, "half": {"f_c": 20.0}},
    "static_friction": {"full": {"T_s": 4.5}, "half": {"T_s": None}},  # None: half-way (below)
    "string_friction": {"full": {"T_sf": 0.3}, "half": {"T_sf": 0.15}},
    "string_stiffness": {"full": {"gj_factor": 0.85}, "half": {"gj_factor": 0.925}},
    "viscous_damping": {"full": {"c_v": 0.03}, "half": {"c_v": 0.015}},
    "top_speed_ramp": {"full": {"ramp": 0.15}, "half": {"ramp": 0.075}},
}


#: Eq. (5.1) as the ``thesis-rig`` preset carries it (regularized: a0 = 0; speed in RPM, gain 1.36),
#: extended to v < 0 as an odd function: the control law of ``--law eq51``.
EQ51 = {"a1": 2.187, "a2": 1.976, "a3": 0.0, "a4": 1.983, "a5": -1.315e-3, "a6": -4.823e-5, "a7": 1.047e-7,
        "ref_rpm": 90.36, "gain": 1.36}
LAWS = ("tucker_wang", "eq51")
_law_name = "tucker_wang"


def use_law(name: str) -> None:
    """Select the bit-rock law of every later simulation: ``tucker_wang`` (the default) or ``eq51``."""
    global _law_name
    if name not in LAWS:
        raise ValueError(f"law = {name!r}: one of {', '.join(LAWS)}")
    _law_name = name


def law(v: float) -> float:
    """The selected law's torque [N m] at W = W_ref, v in rad/s (odd in v, 0 at rest)."""
    if _law_name == "tucker_wang":
        return C0 * (math.tanh(ALPHA0 * v) + ALPHA1 * v / (1.0 + ALPHA2 * v * v))
    p, u = EQ51, abs(v) * 60.0 / (2.0 * math.pi)
    if u <= 0.01 * p["ref_rpm"]:
        t = p["a1"] * u
    elif u <= 0.05 * p["ref_rpm"]:
        t = p["a2"] + p["a3"] * u
    else:
        t = p["a4"] + u * (p["a5"] + u * (p["a6"] + u * p["a7"]))
    return math.copysign(p["gain"] * t, v) if v != 0.0 else 0.0


def law_max() -> float:
    """The law's low-speed maximum at W_ref [N m] (the plain law's static torque), over 0-20 rad/s."""
    return max(law(v) for v in np.linspace(1e-4, 20.0, 20001))


def effect_params(effects, size: str = "full", overrides: dict | None = None) -> dict:
    """Effect name -> parameter dict for the chosen size (with overrides {"eff.key": value})."""
    out = {}
    for name in effects:
        if name not in EFFECTS:
            raise ValueError(f"unknown effect {name!r} (known: {', '.join(EFFECTS)})")
        p = dict(EFFECTS[name][size])
        if name == "static_friction" and p["T_s"] is None:
            p["T_s"] = 0.5 * (law_max() + EFFECTS[name]["full"]["T_s"])
        out[name] = p
    for key, val in (overrides or {}).items():
        name, par = key.split(".")
        out.setdefault(name, dict(EFFECTS[name][size]))[par] = float(val)
    return out


def string_matrices(gj_factor: float = 1.0):
    """Lumped masses (nodes 1..N) and the top-clamped stiffness and modal damping matrices."""
    n = N_SEG
    ks = n * GJ_OVER_L * gj_factor                     # each segment: G J_p / (L/N)
    mseg = DENSITY * J_P * LENGTH_M / n
    m = np.full(n, mseg)
    m[-1] = 0.5 * mseg + J_BIT
    K = np.zeros((n, n))
    for i in range(n):                                  # spring i joins node i (0 = top) and i+1
        K[i, i] += ks
        if i + 1 < n:
            K[i, i] += ks
            K[i, i + 1] -= ks
            K[i + 1, i] -= ks
    M = np.diag(m)
    w2, phi = scipy.linalg.eigh(K, M)                   # mass-normalized: phi^T M phi = I
    w = np.sqrt(w2)
    C = M @ phi @ np.diag(2 * ZETA * w) @ phi.T @ M
    return m, K, C, w, 0.5 * mseg


def wob_series(rng, n: int, dt: float) -> np.ndarray:
    """Recorded (true) WOB [N] on a grid of step dt: band-limited Gaussian, relative std WOB_STD."""
    z = rng.standard_normal(n)
    sos = scipy.signal.butter(4, WOB_BAND_HZ, fs=1.0 / dt, output="sos")
    z = scipy.signal.sosfiltfilt(sos, z)
    z = (z - z.mean()) / z.std()
    return W0 * (1.0 + WOB_STD * z)


def simulate(effects: dict, seed: int = 1, noise: float = 1.0, duration_s: float = DURATION_S,
             settle_s: float = SETTLE_S, dt: float = DT, fs_hz: float = FS_HZ, clean: bool = False) -> dict:
    """Simulate the rig with ``effects`` (name -> parameters, :func:`effect_params`).

    Returns a dict of 500 Hz arrays: time_s (0 at the record's start), bit_speed, top_speed,
    torque_on_bit, wob (noisy, through the sensor chain), and the same without noise under
    ``"clean"`` (before the sensor filter as well).
    """
    rng = np.random.default_rng([seed, 20240])
    e = effects
    gj = e.get("string_stiffness", {}).get("gj_factor", 1.0)
    m, K, C, w, m_half = string_matrices(gj)
    n = N_SEG
    inv_m = 1.0 / m
    Jb = m[-1]
    beta1 = e.get("bit_hysteresis", {}).get("beta1", 0.0)
    beta2 = e.get("bit_hysteresis", {}).get("beta2", 0.0)
    kw = e.get("wob_coupling", {}).get("k", 0.0)
    Tsf = e.get("string_friction", {}).get("T_sf", 0.0)
    cv = e.get("viscous_damping", {}).get("c_v", 0.0)
    Ts_ref = e.get("static_friction", {}).get("T_s", law_max())   # static torque at W_ref
    ramp = e.get("top_speed_ramp", {}).get("ramp", 0.0)
    motor = "top_drive_dynamics" in e
    if motor:
        c_m = e["top_drive_dynamics"]["c_m"]
        J_m = e["top_drive_dynamics"]["J_m"] + m_half
        om_c0 = OMEGA0 + law(OMEGA0) / c_m

    total = settle_s + duration_s
    nsteps = int(round(total / dt))
    stride = int(round(1.0 / (fs_hz * dt)))
    if abs(stride * dt * fs_hz - 1.0) > 1e-9:
        raise ValueError("dt must divide the sampling interval")
    t_steps = np.arange(nsteps + 1) * dt
    # WOB on a 1 ms grid, linearly interpolated to the steps
    wgrid_dt = 1e-3
    ng = int(total / wgrid_dt) + 3
    W = wob_series(rng, ng, wgrid_dt)
    W_steps = np.interp(t_steps, np.arange(ng) * wgrid_dt, W)
    Wlaw = W0 * (1.0 + kw * (W_steps / W0 - 1.0)) if kw else None
    wfac_const = W0 / W_REF
    # commanded top speed (ramp over the record, constant while settling)
    cmd = OMEGA0 * (1.0 + ramp * np.clip((t_steps - settle_s) / duration_s, 0.0, None))

    q = np.zeros(n)          # node angle minus top angle [rad]
    om = np.zeros(n)         # node speeds [rad/s]
    om_top = OMEGA0 if not motor else OMEGA0
    stuck = True
    a_bit = 0.0
    nout = nsteps // stride + 1
    out_v = np.empty(nout)
    out_top = np.empty(nout)
    out_T = np.empty(nout)
    out_W = np.empty(nout)
    stick_events = 0
    law_f = law
    tanh = math.tanh
    k = 0
    for i in range(nsteps + 1):
        wfac = (Wlaw[i] / W_REF) if kw else wfac_const
        rel = om - om_top
        f = -(K @ q) - (C @ rel)          # internal torques on nodes 1..N
        T_str = f[-1]
        v = om[-1]
        Ts = Ts_ref * wfac
        if stuck:
            if abs(T_str) <= Ts + Tsf:
                a_bit = 0.0
                contact = max(-Ts, min(Ts, T_str))
            else:
                stuck = False
                s = 1.0 if T_str > 0 else -1.0
                a_bit = (T_str - s * Tsf) / Jb      # the law is zero at rest
                contact = 0.0
        else:
            s = 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)
            L = law_f(v) * wfac
            R = T_str - s * Tsf - cv * v
            if beta1 > 0.0 and s != 0.0:
                # J a + L (1 + beta1 s tanh(beta2 a)) = R, increasing in a (L s >= 0)
                c = beta1 * s
                lo = (R - L - abs(L) * beta1) / Jb
                hi = (R - L + abs(L) * beta1) / Jb
                a = min(max(a_bit, lo), hi)
                for _ in range(30):
                    th = tanh(beta2 * a)
                    g = Jb * a + L * (1.0 + c * th) - R
                    if abs(g) < 1e-12:
                        break
                    if g > 0:
                        hi = a
                    else:
                        lo = a
                    dg = Jb + L * c * beta2 * (1.0 - th * th)
                    an = a - g / dg
                    a = an if lo < an < hi else 0.5 * (lo + hi)
                    if hi - lo < 1e-10:
                        break
                a_bit = a
                contact = L * (1.0 + c * tanh(beta2 * a))
            else:
                a_bit = (R - L) / Jb
                contact = L
        if i % stride == 0:
            out_v[k] = v
            out_top[k] = om_top
            out_T[k] = contact
            out_W[k] = W_steps[i]
            k += 1
        if i == nsteps:
            break
        # ---- semi-implicit Euler: speeds first, then angles with the new speeds
        acc = f * inv_m
        acc[-1] = a_bit
        if motor:
            f_top = -f.sum()               # reaction of the string on the top
            a_top = (c_m * (om_c0 * cmd[i] / OMEGA0 - om_top) + f_top) / J_m
            om_top_new = om_top + dt * a_top
        else:
            om_top_new = cmd[i + 1]
        om_new = om + dt * acc
        if stuck:
            om_new[-1] = 0.0
        else:
            vn = om_new[-1]
            if (v > 0 and vn <= 0) or (v < 0 and vn >= 0):
                if abs(T_str) <= Ts + Tsf:    # reaches rest with the string torque inside the capacity
                    om_new[-1] = 0.0
                    stuck = True
                    stick_events += 1
        q += dt * (om_new - om_top_new)
        om = om_new
        om_top = om_top_new

    t = np.arange(nout) / fs_hz
    keep = t >= settle_s - 1e-9
    clean_ch = {"bit_speed": out_v, "top_speed": out_top, "torque_on_bit": out_T, "wob": out_W}
    rec = {c: x.copy() for c, x in clean_ch.items()}
    if "sensor_lag" in e:
        b, a = scipy.signal.butter(2, e["sensor_lag"]["f_c"], fs=fs_hz)
        for c in rec:
            zi = scipy.signal.lfilter_zi(b, a) * rec[c][0]
            rec[c], _ = scipy.signal.lfilter(b, a, rec[c], zi=zi)
    for j, c in enumerate(("bit_speed", "top_speed", "torque_on_bit", "wob")):
        rec[c] = rec[c] + noise * NOISE[c] * rng.standard_normal(rec[c].size)
    res = {"time_s": t[keep] - t[keep][0], **{c: rec[c][keep] for c in rec},
           "clean": {c: clean_ch[c][keep] for c in clean_ch}, "stick_events": stick_events,
           "modes_hz": w / (2 * math.pi)}
    return res


def metrics(v: np.ndarray, top: np.ndarray, fs_hz: float = FS_HZ) -> dict:
    """SS = (max - min) / (2 mean top speed), stick fraction (|v| < 5 % of the top speed) and the
    cycle frequency (stick onsets per second; the spectral peak of v otherwise)."""
    om = float(np.mean(top))
    ss = (np.max(v) - np.min(v)) / (2 * om)
    stuck = np.abs(v) < 0.05 * om
    onsets = int(np.sum(stuck[1:] & ~stuck[:-1]))
    x = v - v.mean()
    f = np.fft.rfftfreq(x.size, 1 / fs_hz)
    p = np.abs(np.fft.rfft(x * np.hanning(x.size))) ** 2
    band = (f > 0.5) & (f < 10)
    return {"ss": float(ss), "stick_fraction": float(stuck.mean()), "stick_onsets_per_s": onsets * fs_hz / v.size,
            "spectral_peak_hz": float(f[band][np.argmax(p[band])])}


def write_csv(res: dict, path: str, comments: list[str]) -> None:
    cols = ("bit_speed", "top_speed", "torque_on_bit", "wob")
    data = np.column_stack([res["time_s"]] + [res[c] for c in cols])
    with open(path, "w") as fh:
        for c in comments:
            fh.write(f"# {c}\n")
        fh.write("time_s,bit_speed_rad_s,top_speed_rad_s,torque_on_bit_Nm,wob_N\n")
        np.savetxt(fh, data, fmt=["%.4f", "%.6f", "%.6f", "%.6f", "%.4f"], delimiter=",")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--effects", default="", help="comma-separated effects (" + ", ".join(EFFECTS) + ")")
    ap.add_argument("--size", choices=("full", "half"), default="full")
    ap.add_argument("--set", action="append", default=[], metavar="EFFECT.PAR=VALUE",
                    help="override an effect parameter, e.g. static_friction.T_s=4.0")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--noise", type=float, default=1.0, help="noise factor (3: noise x3)")
    ap.add_argument("--duration", type=float, default=DURATION_S)
    ap.add_argument("--settle", type=float, default=SETTLE_S)
    ap.add_argument("--dt", type=float, default=DT)
    ap.add_argument("--law", choices=LAWS, default="tucker_wang", help="the bit-rock law (eq51: the preset's own)")
    ap.add_argument("--out", help="CSV file to write")
    ap.add_argument("--summary", action="store_true", help="print SS, stick fraction, frequency, torque range")
    a = ap.parse_args(argv)
    use_law(a.law)
    names = [x for x in a.effects.split(",") if x]
    over = dict(s.split("=") for s in a.set)
    eff = effect_params(names, a.size, over)
    t0 = time.time()
    res = simulate(eff, seed=a.seed, noise=a.noise, duration_s=a.duration, settle_s=a.settle, dt=a.dt)
    wall = time.time() - t0
    if a.out:
        write_csv(res, a.out, [f"independent_rig.py (no drillpy code): effects {eff or 'none'}, size {a.size}, "
                               f"seed {a.seed}, noise x{a.noise:g}",
                               (f"Tucker-Wang c0 {C0} alpha0 {ALPHA0} alpha1 {ALPHA1} alpha2 {ALPHA2}" if a.law ==
                                "tucker_wang" else f"Eq. 5.1 {EQ51}") + f"; {N_SEG} lumped "
                               f"segments, modal zeta {ZETA}, dt {a.dt:g} s"])
    if a.summary or not a.out:
        c = res["clean"]
        mt = metrics(c["bit_speed"], c["top_speed"])
        T = c["torque_on_bit"]
        print(f"effects {eff or 'none'}: modes {np.round(res['modes_hz'][:3], 2)} ... Hz; "
              f"SS {mt['ss']:.3f}, stick fraction {mt['stick_fraction']:.3f}, stick onsets {mt['stick_onsets_per_s']:.2f}/s, "
              f"spectral peak {mt['spectral_peak_hz']:.2f} Hz; torque 5-95 % {np.percentile(T, 5):.2f}..{np.percentile(T, 95):.2f} "
              f"N m (mean {T.mean():.2f}); bit speed max {c['bit_speed'].max():.2f} rad/s; top mean "
              f"{c['top_speed'].mean():.3f} sd {c['top_speed'].std():.3f}; wall {wall:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
