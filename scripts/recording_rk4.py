"""The fixed-step RK4 march and the CSV writer that the element recordings share
(scripts/generate_{dry_friction,road_load,clutch_damper,lossy_gear,digital_drive}_data.py): numpy only,
written independently of tvid. Each script keeps its own equations of motion.
"""
import numpy as np


def march(derivative, x0, u_samples, fs, substeps, record):
    """RK4 from x0 over the sample grid t = i/fs, `substeps` equal steps a sample interval,
    the one input u linearly interpolated between its samples, as a recorded channel is
    read. record(x) is called at every sample and its rows returned with the times."""
    n = u_samples.size
    t = np.arange(n) / fs
    h = 1.0 / fs / substeps
    x = np.array(x0, dtype=float)
    rows = []
    for i in range(n):
        rows.append(record(x))
        if i == n - 1:
            break
        u = lambda tau: u_samples[i] + (u_samples[i + 1] - u_samples[i]) * (tau - t[i]) * fs
        for s in range(substeps):
            ts = t[i] + s * h
            k1 = derivative(x, u(ts))
            k2 = derivative(x + 0.5 * h * k1, u(ts + 0.5 * h))
            k3 = derivative(x + 0.5 * h * k2, u(ts + 0.5 * h))
            k4 = derivative(x + h * k3, u(ts + h))
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return t, np.array(rows, dtype=float)


def write_csv(path, header, columns):
    """The columns under their header, 12 significant digits."""
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in zip(*columns):
            f.write(",".join(f"{v:.12g}" for v in row) + "\n")
