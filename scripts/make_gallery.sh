#!/bin/sh
# Draws the images of docs/gallery.md into docs/images/gallery/ (run from the repository
# root after building tvid; a few minutes, most of it the engine fits of the batch). The runs go to
# results/gallery (or $R); the PNGs are reduced to a 64-colour palette to keep them small.
set -e
T=${TVID:-build/release/apps/tvid/tvid}
P="/usr/bin/python3 scripts/plot_report.py"
R=${R:-results/gallery}
G=docs/images/gallery
rm -rf "$R"; mkdir -p "$R" "$G"
$T fit configs/cvt_tipin_clean.yaml -o "$R/cvt" --optimizer lm --set estimation.cost=l2 --quiet
$T sensitivity configs/cvt_tipin_clean.yaml --params "$R/cvt/params.json" -o "$R/cvt/sensitivity" --quiet
$P "$R/cvt" --dpi 70 >/dev/null
$T fit configs/engine_idle.yaml -o "$R/engine" --quiet
$T sensitivity configs/engine_idle.yaml --params "$R/engine/params.json" -o "$R/engine/sensitivity" --quiet
$P "$R/engine" --dpi 70 >/dev/null
$T fit configs/cvt_tipin.yaml -o "$R/multistart" --optimizer multistart --set estimation.cost=l2 \
   --set estimation.multistart.starts=12 --set estimation.multistart.max_iterations=40 --quiet
$P "$R/multistart" --dpi 70 >/dev/null
# The noisy tip-in with a first-order lag (50 ms) of Ttm added to Tds at 0.04 times its change: a
# path from the input that the clearance model does not have (residual_analysis.png names it).
/usr/bin/python3 - data/cvt/tipin_a.csv data/cvt/tipin_clean.csv "$R/lagged.csv" <<'PY'
import sys
def rows(path):  # the data rows of a recording, its comments and header left out
    return [line.split(",") for line in open(path).read().splitlines() if line and not line.startswith("#")][1:]
lag, first, lines = None, None, ["t,Ttm,Tds"]
for (t, u, y), (_, u0, _) in zip(rows(sys.argv[1]), rows(sys.argv[2])):
    lag = float(u0) if lag is None else lag + (float(u0) - lag) * 0.001 / 0.05
    first = float(u0) if first is None else first
    lines.append(f"{t},{u},{float(y) + 0.04 * (lag - first):.10g}")
open(sys.argv[3], "w").write("\n".join(lines) + "\n")
PY
$T fit configs/cvt_tipin.yaml -o "$R/lagged" --set data.file="$(cd "$R" && pwd)/lagged.csv" --optimizer multistart \
   --set estimation.cost=l2 --set estimation.multistart.starts=12 --set estimation.multistart.max_iterations=40 --quiet
$P "$R/lagged" --dpi 70 >/dev/null
$T profile configs/cvt_tipin_clean.yaml --param d_ds --points 9 --params "$R/cvt/params.json" -o "$R/profile" \
   --set estimation.cost=l2 --quiet
$P "$R/profile" --dpi 70 >/dev/null
$T fit configs/aalto_bench.yaml -o "$R/bench" --quiet
$T modes configs/aalto_bench.yaml --params "$R/bench/params.json" -o "$R/bench-modes" --quiet
$T frf configs/aalto_bench.yaml --params "$R/bench/params.json" --input T_prop --output torque_lower \
   -o "$R/bench-frf" --quiet
for d in bench bench-modes bench-frf; do $P "$R/$d" --dpi 70 >/dev/null; done
$T batch configs/engine_idle.yaml --cycles 2-7 --cross -o "$R/engine-batch" \
   --set estimation.lm.max_iterations=30 --quiet
$P "$R/engine-batch" --dpi 70 >/dev/null
for f in fit residual residual_ratio cost_history sensitivity_Tds sensitivity_ranking; do
  cp "$R/cvt/plots/$f.png" "$G/cvt_$f.png"
done
for f in fit residual residual_ratio sensitivity_omega_dw sensitivity_ranking; do
  cp "$R/engine/plots/$f.png" "$G/engine_$f.png"
done
cp "$R/multistart/plots/multistart.png" "$G/cvt_multistart.png"
cp "$R/multistart/plots/residual_analysis.png" "$G/cvt_residual_analysis.png"
cp "$R/lagged/plots/residual_analysis.png" "$G/cvt_lagged_residual_analysis.png"
cp "$R/profile/plots/profile.png" "$G/cvt_profile.png"
cp "$R/engine/plots/orders.png" "$G/engine_orders.png"
cp "$R/bench/plots/spectra.png" "$G/bench_spectra.png"
cp "$R/bench-modes/plots/modes.png" "$G/bench_modes.png"
cp "$R/bench-frf/plots/frf.png" "$G/bench_frf.png"
cp "$R/engine-batch/plots/cross_matrix.png" "$G/engine_cross_matrix.png"
cp "$R/engine-batch/plots/parameter_spread.png" "$G/engine_parameter_spread.png"
/usr/bin/python3 - "$G" <<'PY'
import os, sys
from PIL import Image  # Debian python3-pil, which matplotlib needs anyway
for name in sorted(os.listdir(sys.argv[1])):
    path = os.path.join(sys.argv[1], name)
    Image.open(path).convert("RGB").quantize(colors=64).save(path, optimize=True)
    print(f"{path}: {os.path.getsize(path) // 1024} kB")
PY
