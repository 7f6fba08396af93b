#!/usr/bin/env python3
"""A second independent simulator of the test rig for checking ``drillpy loop``: an exponential
Stribeck law, Rayleigh damping, 5 lumped segments and an exact linear step.

Written separately from ``independent_rig.py`` (its author did not read it) and sharing no code with
drillpy (NumPy and SciPy only), so that the loop meets a second truth it was not built around:

* **Bar**: length 1.7 m, GJ/L = 3.08 N m/rad overall, steel radius 2.5 mm, density 7850, lumped
  into ``NSEG`` = 5 segments; nodes 0 (top) .. 5 (bit), half a segment's inertia at each end of a
  segment, the bit disk (9.33e-3 kg m^2) on node 5; first mode 2.89 Hz.
* **Damping**: Rayleigh, C = alpha M + beta K, scaled so that the first mode has zeta = ``ZETA1`` =
  0.05; the alpha M part acts on the speeds relative to the top (no drag on the rigid rotation).
* **Integration**: the linear part exactly (matrix exponential, inputs held over the step) at
  ``DT`` = 1e-5 s; the bit torque, the only nonlinear input, per step with a true stick (the bit
  stays at rest while the torque holding it there is within the break-away bound).
* **Bit-rock law**: T(v) = W / W_ref (Tc + (Ts0 - Tc) exp(-|v| / vs) + cv |v|) sign(v), Tc 1.6 N m,
  Ts0 2.6 N m (the break-away torque, the law's value at rest), vs 2 rad/s, cv -0.02 N m s/rad.
  At 7.5 rad/s and 557 N the clean rig stick-slips with SS 1.28, stick fraction 0.30, 2.60 Hz.
* **Record**: 5 s of settling, then 30 s at 1000 Hz; WOB W0 (1 + 0.10 z), z low-passed at 1.5 Hz
  (the law takes W0 unless ``wob_coupling``); white noise 0.03 rad/s on both speeds, 0.03 N m on
  the torque, 2 N on the WOB.

Effects (one per record, by name): ``wob_coupling`` (the law at W(t)), ``bit_hysteresis``
(T (1 + 0.2 tanh(0.05 a) sign(v))), ``top_drive_dynamics`` (J_m 0.02 kg m^2, c_m ``--cm``, command
``--omega-c``: c_m 0.1 with 23.809 rad/s stick-slips at a mean top speed of 7.5 rad/s; c_m 0.3
damps the cycle out), ``sensor_lag`` (every channel through a causal 2nd-order Butterworth at
12 Hz), ``static_friction`` (break-away at 4.2 N m), ``string_stiffness`` (GJ x 0.87),
``string_friction`` (Coulomb 0.3 N m on the bit, not in the recorded torque), ``viscous_damping``
(0.03 N m s/rad on the bit, not recorded), ``ramp`` (top speed +12 % over the record, outside the
loop's catalogue), ``clean``.

    python3 benchmarks/stribeck_rig.py wob_coupling --seed 11 --out rec.csv
    PYTHONPATH=python python3 benchmarks/loop_independent.py --simulator stribeck --dir /tmp/ls
"""
import argparse
import json
import math

import numpy as np
from scipy.linalg import expm, eigvals
from scipy.signal import butter, lfilter, lfilter_zi

# ---------------- rig constants (Table 5.1-like) ----------------
L = 1.7
K_OVERALL = 3.08            # N m/rad
GJ = K_OVERALL * L
R_BAR = 2.5e-3
RHO = 7850.0
J_BIT = 9.33e-3
NSEG = 5
ZETA1 = 0.05
W0 = 557.0
WREF = 557.0

# bit-rock law
LAW = dict(Tc=1.6, Ts0=2.6, vs=2.0, cv=-0.02)

DT = 1e-5
FS = 1000.0
T_SETTLE = 5.0
T_REC = 30.0


def build_matrices(k_scale=1.0, motor=None):
    """Return (A, B, info) of the continuous linear system.

    prescribed top: x = [phi0, phi1..phi5, w1..w5], u = [Omega_top, T_bit]
    motor top     : x = [phi0, w0, phi1..phi5, w1..w5], u = [Omega_c, T_bit]
    """
    Ip = math.pi * R_BAR ** 4 / 2.0
    Jbar = RHO * Ip * L
    jseg = Jbar / NSEG
    kseg = NSEG * K_OVERALL * k_scale
    n = NSEG + 1                       # nodes 0..5
    J = np.full(n, jseg)
    J[0] = jseg / 2
    J[-1] = jseg / 2 + J_BIT
    Kf = np.zeros((n, n))
    for e in range(NSEG):
        Kf[e, e] += kseg
        Kf[e + 1, e + 1] += kseg
        Kf[e, e + 1] -= kseg
        Kf[e + 1, e] -= kseg
    # first mode (top clamped, bit free), undamped
    Kc = Kf[1:, 1:]
    Mc = np.diag(J[1:])
    w2 = np.sort(np.real(eigvals(np.linalg.solve(Mc, Kc))))
    w1 = math.sqrt(w2[0])

    def damped_zeta1(a, b):
        C = a * Mc + b * Kc
        Aq = np.block([[np.zeros_like(Mc), np.eye(len(Mc))],
                       [-np.linalg.solve(Mc, Kc), -np.linalg.solve(Mc, C)]])
        ev = eigvals(Aq)
        ev = ev[np.imag(ev) > 1e-6]
        lam = ev[np.argmin(np.abs(ev))]
        return -np.real(lam) / abs(lam), abs(np.imag(lam))

    # Rayleigh coefficients: even split, rescaled to hit ZETA1 exactly on mode 1
    s = 1.0
    for _ in range(30):
        a, b = s * ZETA1 * w1, s * ZETA1 / w1
        z, wd = damped_zeta1(a, b)
        s *= ZETA1 / z
    alpha, beta = s * ZETA1 * w1, s * ZETA1 / w1
    z1, wd1 = damped_zeta1(alpha, beta)

    # equations per node i (absolute angle phi_i, speed w_i):
    # J_i w_i' = -sum_j Kf_ij phi_j - beta sum_j Kf_ij w_j - alpha J_i (w_i - w_top) [- T on bit]
    nf = NSEG  # free nodes 1..5
    if motor is None:
        nx = 1 + 2 * nf
        A = np.zeros((nx, nx))
        B = np.zeros((nx, 2))
        def ip(i):  # phi index of node i (0..5)
            return i

        def iw(i):  # w index of node i (1..5)
            return 1 + nf + (i - 1)

        B[0, 0] = 1.0               # phi0' = Omega_top
        for i in range(1, n):
            A[ip(i), iw(i)] = 1.0
            r = iw(i)
            for j in range(n):
                A[r, ip(j)] += -Kf[i, j] / J[i]
                if j == 0:
                    B[r, 0] += -beta * Kf[i, 0] / J[i]
                else:
                    A[r, iw(j)] += -beta * Kf[i, j] / J[i]
            A[r, r] += -alpha
            B[r, 0] += alpha
        B[iw(n - 1), 1] = -1.0 / J[n - 1]
        ibit = iw(n - 1)
        itop = None
    else:
        Jm, cm = motor
        nx = 2 + 2 * nf
        A = np.zeros((nx, nx))
        B = np.zeros((nx, 2))
        def ip(i):  # phi0 -> 0, phi_i -> 1 + i (2..6)
            return 0 if i == 0 else 1 + i

        def iw(i):  # w0 -> 1, w_i -> 1 + nf + i (7..11)
            return 1 if i == 0 else 1 + nf + i

        Jt = Jm + J[0]
        for i in range(n):
            A[ip(i), iw(i)] = 1.0
            r = iw(i)
            Ji = Jt if i == 0 else J[i]
            for j in range(n):
                A[r, ip(j)] += -Kf[i, j] / Ji
                A[r, iw(j)] += -beta * Kf[i, j] / Ji
            if i > 0:
                A[r, r] += -alpha
                A[r, iw(0)] += alpha
        A[iw(0), iw(0)] += -cm / Jt
        B[iw(0), 0] = cm / Jt
        B[iw(n - 1), 1] = -1.0 / J[n - 1]
        ibit = iw(n - 1)
        itop = iw(0)
    info = dict(alpha=alpha, beta=beta, zeta1=z1, f1_undamped=w1 / 2 / math.pi,
                f1_damped=wd1 / 2 / math.pi, kseg=kseg, Jnodes=J.tolist(), Jbar=Jbar)
    return A, B, ibit, itop, info


def discretize(A, B, dt):
    nx, nu = B.shape
    M = np.zeros((nx + nu, nx + nu))
    M[:nx, :nx] = A
    M[:nx, nx:] = B
    E = expm(M * dt)
    return E[:nx, :nx], E[:nx, nx:]


def wob_series(rng, n, fs):
    """W(t) = W0 (1 + 0.10 z), z unit-variance white noise low-passed at 1.5 Hz."""
    pad = int(10 * fs)
    e = rng.standard_normal(n + pad)
    b, a = butter(2, 1.5, fs=fs)
    z = lfilter(b, a, e)[pad:]
    z = (z - z.mean()) / z.std()
    return W0 * (1.0 + 0.10 * z)


def simulate(effect=None, seed=0, top_speed=7.5, law=None, dt=DT, t_settle=T_SETTLE,
             t_rec=T_REC, fs=FS, omega_c=None, quiet=False, motor_params=(0.02, 0.3)):
    law = dict(LAW if law is None else law)
    Tc, Ts0, vs, cv = law["Tc"], law["Ts0"], law["vs"], law["cv"]
    rng = np.random.default_rng(seed)
    k_scale = 0.87 if effect == "string_stiffness" else 1.0
    motor = tuple(motor_params) if effect == "top_drive_dynamics" else None
    A, B, ibit, itop, info = build_matrices(k_scale, motor)
    Phi, G = discretize(A, B, dt)
    gu = G[:, 0].copy()
    gT = G[:, 1].copy()
    gTb = gT[ibit]                 # < 0
    assert gTb < 0

    t_tot = t_settle + t_rec
    nsamp = int(round(t_tot * fs))
    sub = int(round(1.0 / (fs * dt)))
    W = wob_series(rng, nsamp, fs)

    # prescribed top speed profile (per recorded sample, ZOH within a sample)
    if effect == "ramp":
        tt = np.arange(nsamp) / fs
        Om = np.where(tt < t_settle, top_speed,
                      top_speed * (1.0 + 0.12 * (tt - t_settle) / t_rec))
    else:
        Om = np.full(nsamp, top_speed)
    if motor is not None:
        if omega_c is None:
            raise ValueError("omega_c needed")
        u0 = np.full(nsamp, omega_c)
    else:
        u0 = Om

    # extra (unrecorded) bit torques
    Tf = 0.3 if effect == "string_friction" else 0.0
    cvisc = 0.03 if effect == "viscous_damping" else 0.0
    hyst = effect == "bit_hysteresis"
    T_break_fixed = 4.2 if effect == "static_friction" else None

    x = np.zeros(Phi.shape[0])
    if motor is not None:
        x[itop] = top_speed
    stuck = True
    a_prev = 0.0

    rec_bit = np.empty(nsamp)
    rec_top = np.empty(nsamp)
    rec_tq = np.empty(nsamp)
    n_break = 0
    Phi_ = Phi
    exp = math.exp
    tanh = math.tanh
    for ks in range(nsamp):
        Wk = W[ks] if effect == "wob_coupling" else W0
        scale = Wk / WREF
        Sbreak = (T_break_fixed if T_break_fixed is not None else Ts0 * scale)
        Sbound = Sbreak + Tf
        uk = u0[ks]
        free_u = gu * uk
        tq_rec = 0.0
        for _ in range(sub):
            free = Phi_ @ x + free_u
            fb = free[ibit]
            vb = x[ibit]
            if stuck:
                Tstar = -fb / gTb          # torque keeping the bit at rest over this step
                if abs(Tstar) <= Sbound:
                    T = Tstar
                    x = free + gT * T
                    x[ibit] = 0.0
                    tq_rec = Tstar * (Sbreak / Sbound) if Tf > 0 else Tstar
                    continue
                # break away in the direction of the string torque
                stuck = False
                n_break += 1
                s = 1.0 if Tstar > 0 else -1.0
                Tcont = scale * Ts0 * s        # law at v = 0+
                T = Tcont + Tf * s
                x = free + gT * T
                tq_rec = Tcont
                continue
            s = 1.0 if vb > 0 else -1.0
            av = abs(vb)
            T0 = scale * (Tc + (Ts0 - Tc) * exp(-av / vs) + cv * av) * s
            if hyst:
                # implicit in the acceleration a = (v_new - v)/dt, v_new = fb + gTb*T
                # T = T0 (1 + 0.2 tanh(0.05 a) s); Newton on a
                a = a_prev
                for _it in range(30):
                    th = tanh(0.05 * a)
                    Tc_ = T0 * (1.0 + 0.2 * th * s)
                    Ttot = Tc_ + (Tf * s) + cvisc * vb
                    g = a - (fb + gTb * Ttot - vb) / dt
                    dg = 1.0 - gTb * T0 * 0.2 * s * 0.05 * (1 - th * th) / dt
                    da = -g / dg
                    a += da
                    if abs(da) < 1e-9 * (1 + abs(a)):
                        break
                th = tanh(0.05 * a)
                Tcont = T0 * (1.0 + 0.2 * th * s)
            else:
                Tcont = T0
            T = Tcont + Tf * s + cvisc * vb
            vnew = fb + gTb * T
            if vnew * vb <= 0.0:
                # speed would cross zero in this step: try to stick
                Tstar = -fb / gTb
                if abs(Tstar) <= Sbound:
                    stuck = True
                    x = free + gT * Tstar
                    x[ibit] = 0.0
                    tq_rec = Tstar * (Sbreak / Sbound) if Tf > 0 else Tstar
                    a_prev = 0.0
                    continue
            x = free + gT * T
            a_prev = (x[ibit] - vb) / dt
            tq_rec = Tcont
        rec_bit[ks] = x[ibit]
        rec_top[ks] = x[itop] if itop is not None else Om[ks]
        rec_tq[ks] = tq_rec
    return dict(bit=rec_bit, top=rec_top, tq=rec_tq, wob=W, info=info, n_break=n_break,
                fs=fs, t_settle=t_settle)


def metrics(bit, top, fs):
    ss = (bit.max() - bit.min()) / (2 * top.mean())
    stick = bit == 0.0
    sf = stick.mean()
    onsets = np.count_nonzero(stick[1:] & ~stick[:-1])
    dur = len(bit) / fs
    # PSD peak of bit speed
    b = bit - bit.mean()
    P = np.abs(np.fft.rfft(b * np.hanning(len(b)))) ** 2
    f = np.fft.rfftfreq(len(b), 1 / fs)
    m = (f > 0.3) & (f < 20)
    fpk = f[m][np.argmax(P[m])]
    return dict(SS=float(ss), stick_fraction=float(sf), stick_onsets_per_s=onsets / dur,
                psd_peak_hz=float(fpk), mean_top=float(top.mean()), mean_bit=float(bit.mean()),
                max_bit=float(bit.max()), min_bit=float(bit.min()))


def make_record(effect, seed, path, omega_c=None, top_speed=7.5, cm=0.3):
    eff = None if effect == "clean" else effect
    r = simulate(eff, seed=seed, top_speed=top_speed, omega_c=omega_c, motor_params=(0.02, cm))
    fs = r["fs"]
    n0 = int(round(r["t_settle"] * fs))
    bit, top, tq, wob = r["bit"], r["top"], r["tq"], r["wob"]
    if eff == "sensor_lag":
        b, a = butter(2, 12.0, fs=fs)
        zi = lfilter_zi(b, a)
        bit, top, tq, wob = [lfilter(b, a, y, zi=zi * y[0])[0] for y in (bit, top, tq, wob)]
    bit, top, tq, wob = bit[n0:], top[n0:], tq[n0:], wob[n0:]
    met = metrics(r["bit"][n0:], r["top"][n0:], fs)
    nrng = np.random.default_rng(seed + 1000)
    n = len(bit)
    bit_m = bit + 0.03 * nrng.standard_normal(n)
    top_m = top + 0.03 * nrng.standard_normal(n)
    tq_m = tq + 0.03 * nrng.standard_normal(n)
    wob_m = wob + 2.0 * nrng.standard_normal(n)
    t = np.arange(n) / fs
    with open(path, "w") as fh:
        fh.write(f"# stribeck_rig.py; effect={effect}; seed={seed}; omega_c={omega_c}; cm={cm}\n")
        fh.write(f"# truth metrics (noise-free): {json.dumps(met)}\n")
        fh.write("time_s,bit_speed_rad_s,top_speed_rad_s,torque_on_bit_Nm,wob_N\n")
        for row in zip(t, bit_m, top_m, tq_m, wob_m):
            fh.write("%.3f,%.6f,%.6f,%.6f,%.4f\n" % row)
    return met, r["info"]


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("effect")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--omega-c", type=float, default=None)
    ap.add_argument("--cm", type=float, default=0.3, help="motor constant (top_drive_dynamics)")
    a = ap.parse_args()
    met, info = make_record(a.effect, a.seed, a.out, omega_c=a.omega_c, cm=a.cm)
    print(json.dumps(dict(effect=a.effect, seed=a.seed, metrics=met, info=info)))
