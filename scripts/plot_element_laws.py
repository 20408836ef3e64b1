#!/usr/bin/python3
"""Draw the laws of tvid's loss and spring elements, one figure each, from the formulas
written out here (numpy and matplotlib with the Agg backend):

    law_friction.png          friction torque against relative speed: viscous and Coulomb, with a
                              Stribeck rise, and with both different in the two directions
    law_road_load.png         road load against speed, its three terms, and its rounding at zero
    law_multistage_spring.png multi-stage spring torque against twist: odd, with free play, asymmetric
    law_gear_efficiency.png   a lossy gear's output factor f = eta^tanh(P/P_s) against the power
    law_sampled_controller.png a position step under a continuous PD and under the same gains
                              sampled every 5 ms with one period's delay: the held torque

    /usr/bin/python3 scripts/plot_element_laws.py [OUT_DIR]      (default docs/images)
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

plt.rcParams.update({"font.size": 11, "axes.grid": True, "grid.alpha": 0.35, "legend.fontsize": 10,
                     "lines.linewidth": 2.0})
SIZE = (8.0, 4.2)   # inches, at 100 dpi: 800 px wide


def friction(v, c, coulomb, c_negative=None, coulomb_negative=None, breakaway=None, stribeck_speed=1.0,
             smoothing_speed=0.1):
    """The friction torque at relative speed v (tvid's `friction`)."""
    c_negative = c if c_negative is None else c_negative
    coulomb_negative = coulomb if coulomb_negative is None else coulomb_negative
    breakaway = coulomb if breakaway is None else breakaway
    s = np.tanh(v / smoothing_speed)
    p = 0.5 * (1.0 + s)
    c_eff = c_negative + (c - c_negative) * p
    f_eff = coulomb_negative + (coulomb - coulomb_negative) * p
    return c_eff * v + (f_eff + (breakaway - coulomb) * np.exp(-(v / stribeck_speed) ** 2)) * s


def road_load(w, a, b, c, smoothing_speed=0.1):
    return a * np.tanh(w / smoothing_speed) + b * w + c * w * np.abs(w)


def softplus(x, s):
    z = x / s
    return s * (np.maximum(z, 0.0) + np.log1p(np.exp(-np.abs(z))))


def multistage_spring(th, stages, stages_negative=None, smoothing_angle=0.001):
    """The spring torque at twist th: stages [(angle, k), ...] from zero outwards, the negative
    side's own stages (angles as magnitudes) or the positive side's (an odd law)."""
    stages_negative = stages if stages_negative is None else stages_negative
    torque = np.zeros_like(th)
    for side, sign in ((stages, 1.0), (stages_negative, -1.0)):
        k_before = 0.0
        for angle, k in sorted(side):
            torque += sign * (k - k_before) * softplus(sign * th - angle, smoothing_angle)
            k_before = k
    return torque


def save(fig, out, name, layout=True):
    if layout:
        fig.tight_layout()
    path = os.path.join(out, name)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(path)


def draw_friction(out):
    v = np.linspace(-5, 5, 2001)
    vz = np.linspace(-0.4, 0.4, 2001)
    laws = [("viscous + Coulomb:\nc = 0.2 N m s/rad\ncoulomb = 2 N m", "-",
             dict(c=0.2, coulomb=2.0)),
            ("+ Stribeck rise:\nbreakaway = 4 N m\nstribeck_speed = 1.5 rad/s", "--",
             dict(c=0.2, coulomb=2.0, breakaway=4.0, stribeck_speed=1.5)),
            ("+ backwards its own:\nc_negative = 0.3 N m s/rad\ncoulomb_negative = 1.4 N m", "-",
             dict(c=0.2, coulomb=2.0, c_negative=0.3, coulomb_negative=1.4, breakaway=4.0, stribeck_speed=1.5))]
    fig, (ax, az) = plt.subplots(1, 2, figsize=(SIZE[0], 5.4), gridspec_kw={"width_ratios": [3, 2]})
    for (label, style, kw), z in zip(laws, [2, 3, 1]):   # the dashed curve on top of the one it shares v > 0 with
        line, = ax.plot(v, friction(v, smoothing_speed=0.05, **kw), style, label=label, zorder=z)
        az.plot(vz, friction(vz, smoothing_speed=0.05, **kw), style, color=line.get_color(), zorder=z)
    ax.set_xlabel("relative speed v [rad/s]")
    ax.set_ylabel("friction torque T [N m]")
    ax.set_title("torque −T on a, +T on b", fontsize=10)
    az.set_xlabel("relative speed v [rad/s]")
    az.set_title("near zero: sign smoothed over 0.05 rad/s", fontsize=10)
    for a in (ax, az):
        a.axhline(0, color="k", lw=0.6)
        a.axvline(0, color="k", lw=0.6)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=9.5, frameon=False)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    save(fig, out, "law_friction.png", layout=False)


def draw_road_load(out):
    a, b, c = 6.0, 0.08, 0.003
    w = np.linspace(-30, 120, 1501)
    wz = np.linspace(-0.5, 0.5, 1001)
    fig, (ax, az) = plt.subplots(1, 2, figsize=SIZE, gridspec_kw={"width_ratios": [3, 2]})
    ax.plot(w, road_load(w, a, b, c), color="k", label="road load T")
    ax.plot(w, a * np.tanh(w / 0.1), "--", label="rolling a·tanh(ω/0.1)")
    ax.plot(w, b * w, "--", label="linear b·ω")
    ax.plot(w, c * w * np.abs(w), "--", label="aerodynamic c·ω·|ω|")
    ax.set_xlabel("speed ω [rad/s]")
    ax.set_ylabel("road load torque T [N m]")
    ax.set_title("a = 6 N m, b = 0.08 N m s/rad, c = 0.003 N m s²/rad²", fontsize=10)
    ax.legend(loc="upper left")
    az.plot(wz, road_load(wz, a, b, c), color="k")
    az.set_xlabel("speed ω [rad/s]")
    az.set_title("through zero: smoothed over 0.1 rad/s", fontsize=10)
    for x in (ax, az):
        x.axhline(0, color="k", lw=0.6)
        x.axvline(0, color="k", lw=0.6)
    save(fig, out, "law_road_load.png")


def draw_multistage_spring(out):
    laws = [("odd, 2 stages:\n300 N m/rad to 0.03 rad,\nthen 3000 N m/rad", "-",
             ([(0.0, 300.0), (0.03, 3000.0)], None)),
            ("odd, free play to 0.01 rad,\nthen 300, 1000 from 0.04 rad,\n4000 N m/rad from 0.08 rad", "--",
             ([(0.01, 300.0), (0.04, 1000.0), (0.08, 4000.0)], None)),
            ("asymmetric: drive 300 to 0.05 rad,\nthen 2000 N m/rad; coast 300\nto −0.02 rad, then 4000 N m/rad", "-",
             ([(0.0, 300.0), (0.05, 2000.0)], [(0.0, 300.0), (0.02, 4000.0)]))]
    th = np.linspace(-0.12, 0.12, 2401)
    thz = np.linspace(-0.06, 0.06, 2401)
    fig, (ax, az) = plt.subplots(1, 2, figsize=(SIZE[0], 5.4), gridspec_kw={"width_ratios": [3, 2]})
    for label, style, (stages, negative) in laws:
        line, = ax.plot(th, multistage_spring(th, stages, negative, 0.002), style, label=label)
        az.plot(thz, multistage_spring(thz, stages, negative, 0.002), style, color=line.get_color())
    ax.set_ylim(-260, 260)
    az.set_ylim(-40, 40)
    ax.set_title("torque −T on a, +T on b", fontsize=10)
    az.set_title("the first stages; corners rounded\nover smoothing_angle = 0.002 rad", fontsize=10)
    for a in (ax, az):
        a.axhline(0, color="k", lw=0.6)
        a.axvline(0, color="k", lw=0.6)
        a.set_xlabel("twist θ = θa − θb [rad]")
    ax.set_ylabel("spring torque T [N m]")
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=9.5, frameon=False)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    save(fig, out, "law_multistage_spring.png", layout=False)


def draw_gear_efficiency(out):
    power = np.linspace(-5, 5, 1001)
    fig, ax = plt.subplots(figsize=SIZE)
    for eta in (0.95, 0.9, 0.8):
        ax.plot(power, eta ** np.tanh(power / 1.0), label=f"η = {eta}  (1/η = {1 / eta:.3f})")
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel("power into the mesh from shaft a, P = T·ωa [W]")
    ax.set_ylabel(r"output factor $f = \eta^{\tanh(P/P_s)}$")
    ax.set_title("output torque n·T·f, P_s = 1 W:  P > 0, a drives b: f → η;  P < 0, b drives a: f → 1/η",
                 fontsize=10)
    ax.legend(loc="lower left")
    save(fig, out, "law_gear_efficiency.png")


def draw_sampled_controller(out):
    """One inertia (J = 0.002 kg m^2) under kp = 2 N m/rad, kd = 0.08 N m s/rad and a 0.5 rad
    setpoint step at 10 ms; continuous, and sampled at Ts = 5 ms with one period's delay, the
    speed the backward difference of the sampled angles. RK4 at 0.05 ms."""
    j, kp, kd, ts, h, t_end = 0.002, 2.0, 0.08, 0.005, 5e-5, 0.2
    n = int(round(t_end / h))
    t = np.arange(n + 1) * h
    ref = np.where(t >= 0.01, 0.5, 0.0)

    def run(sampled):
        th, w, held, angles, commands = 0.0, 0.0, 0.0, [0.0, 0.0], [0.0, 0.0]
        every = int(round(ts / h))
        theta, torque = np.empty(n + 1), np.empty(n + 1)
        for i in range(n + 1):
            if sampled and i > 0 and i % every == 0:
                angles = [angles[1], th]
                rate = (angles[1] - angles[0]) / ts
                commands = [commands[1], kp * (ref[i] - th) - kd * rate]
                held = commands[0]
            u = held if sampled else kp * (ref[i] - th) - kd * w
            theta[i], torque[i] = th, u

            def f(a, b):
                return b, ((held if sampled else kp * (ref[i] - a) - kd * b)) / j

            k1 = f(th, w)
            k2 = f(th + 0.5 * h * k1[0], w + 0.5 * h * k1[1])
            k3 = f(th + 0.5 * h * k2[0], w + 0.5 * h * k2[1])
            k4 = f(th + h * k3[0], w + h * k3[1])
            th += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        return theta, torque

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True)
    for sampled, label, style in ((False, "continuous PD", "-"), (True, "sampled, Ts = 5 ms, delay 1·Ts", "-")):
        theta, torque = run(sampled)
        top.plot(t * 1e3, theta, style, label=label)
        bottom.step(t * 1e3, torque, style, where="post", label=label)
    top.plot(t * 1e3, ref, "k--", lw=1.0, label="setpoint")
    top.set_ylabel("angle θ [rad]")
    top.legend(loc="lower right")
    bottom.set_ylabel("torque T [N m]")
    bottom.set_xlabel("time [ms]")
    bottom.set_title("the sampled command is held between samples and applied one period late", fontsize=10)
    save(fig, out, "law_sampled_controller.png")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "docs", "images")
    os.makedirs(out, exist_ok=True)
    draw_friction(out)
    draw_road_load(out)
    draw_multistage_spring(out)
    draw_gear_efficiency(out)
    draw_sampled_controller(out)
