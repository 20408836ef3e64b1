#!/usr/bin/python3
"""scripts/report_plots/spectra.py on a small report written here: spectra.png from
spectra.csv with the modes of summary.json (the rigid-body one left out), orders.png from
orders.csv, and nothing from a folder without either file.

    test_spectra_plots.py SOURCE_DIR WORK_DIR
"""
import json
import math
import os
import sys

source_dir, work_dir = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(source_dir, "scripts"))
from report_plots import spectra  # noqa: E402

report = os.path.join(work_dir, "report")
os.makedirs(report, exist_ok=True)
unit = "[(N m)^2/Hz]"
with open(os.path.join(report, "spectra.csv"), "w") as f:
    f.write(f"split,frequency [Hz],T_measured_psd {unit},T_simulated_psd {unit},T_residual_psd {unit}\n")
    for split in ("estimation", "validation"):
        for k in range(129):
            fk = k * 500 / 128
            measured = 1e-2 / (1 + (fk / 20) ** 4) + 1e-5
            residual = 1e-5 + 1e-3 * math.exp(-((fk - 54) / 3) ** 2)
            f.write(f"{split},{fk},{measured},{measured - residual + 2e-5},{residual}\n")
with open(os.path.join(report, "orders.csv"), "w") as f:
    f.write("split,window,cycle,output,unit,order,measured_amplitude,measured_phase [deg],simulated_amplitude,"
            "simulated_phase [deg],residual_amplitude,residual_phase [deg]\n")
    for cycle in (2, 3):
        for m in range(1, 25):
            f.write(f"estimation,cycle {cycle},{cycle},T,N m,{m / 2},{1 / m},10,{0.9 / m},12,{0.1 / m},5\n")
with open(os.path.join(report, "summary.json"), "w") as f:
    json.dump({"experiment": "test",
               "residual_spectrum": {"estimation": {"T": {"unit": "N m", "frequency": {
                   "peak_hz": 54.7, "band_hz": [51.9, 57.4], "share": 0.6, "variance": 0.01},
                   "order": {"order": 0.5, "amplitude": 0.1, "share": 0.3, "orders_share": 0.5, "max_order": 12,
                             "variance": 0.01, "cycles": 2}}}},
               "modes": {"modes": [{"frequency_hz": 0.0, "kind": "rigid_body"},
                                   {"frequency_hz": 54.0, "kind": "torsional"}]}}, f)

plots = os.path.join(work_dir, "plots")
os.makedirs(plots, exist_ok=True)
written = spectra.draw(report, plots, 60)
assert written == ["spectra.png", "orders.png"], written
for name in written:
    with open(os.path.join(plots, name), "rb") as png:
        assert png.read(8) == b"\x89PNG\r\n\x1a\n", name
    assert os.path.getsize(os.path.join(plots, name)) > 5000, name

empty = os.path.join(work_dir, "empty")
os.makedirs(empty, exist_ok=True)
assert spectra.draw(empty, plots, 60) == []
print("spectra.py: spectra.png and orders.png drawn; nothing from an empty folder")
