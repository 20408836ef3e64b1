#!/usr/bin/python3
"""scripts/plot_report.py on damaged and unusual report directories, made from real ones.

tvid writes a fit report (the noise-free CVT tip-in, least squares, < 1 s), its
sensitivity run, its modes, its frequency response and a profile of 5 points; each case
copies one of them and damages one file. Every damaged input must end with exit status 2
and one line on stderr that names the file (and the key or column), never a traceback,
and no figure for it. A report whose output is named `w/motor` must be drawn, its
figures' names made safe, nothing written outside the output folder.

    test_plot_report_inputs.py SOURCE_DIR WORK_DIR TVID
"""
import json
import os
import shutil
import subprocess
import sys

source_dir, work_dir, tvid = sys.argv[1], sys.argv[2], sys.argv[3]
try:
    import matplotlib  # noqa: F401
except ImportError:
    print("SKIPPED: /usr/bin/python3 cannot import matplotlib (Debian: apt-get install python3-matplotlib)")
    sys.exit(0)

script = os.path.join(source_dir, "scripts", "plot_report.py")
config = os.path.join(source_dir, "configs", "cvt_tipin_clean.yaml")
shutil.rmtree(work_dir, ignore_errors=True)
os.makedirs(work_dir)


def run(*command):
    r = subprocess.run(command, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(command)}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


# The real directories: a fit report with its sensitivity run, modes, FRF and a profile.
report = os.path.join(work_dir, "report")
run(tvid, "fit", config, "-o", report, "--optimizer", "lm", "--set", "estimation.cost=l2", "--quiet")
params = os.path.join(report, "params.json")
run(tvid, "sensitivity", config, "--params", params, "-o", os.path.join(report, "sensitivity"), "--quiet")
modes = os.path.join(work_dir, "modes")
run(tvid, "modes", config, "--params", params, "-o", modes, "--quiet")
frf = os.path.join(work_dir, "frf")
run(tvid, "frf", config, "--params", params, "--input", "Ttm", "--output", "Tds", "-o", frf, "--quiet")
profile = os.path.join(work_dir, "profile")
run(tvid, "profile", config, "--param", "d_ds", "--points", "5", "-o", profile, "--set", "estimation.optimizer=lm",
    "--set", "estimation.cost=l2", "--set", "parameters.rho1=1.42855", "--quiet")

cases = 0


def damaged(name, source, damage):
    """A copy of `source` as WORK_DIR/name, damaged by damage(copy)."""
    copy = os.path.join(work_dir, name)
    shutil.copytree(source, copy)
    damage(copy)
    return copy


def write(path, text, mode="w"):
    with open(path, mode) as f:
        f.write(text)


def edit_json(path, change):
    with open(path) as f:
        document = json.load(f)
    change(document)
    write(path, json.dumps(document))


def refused(directory, *expected, args=()):
    """plot_report.py DIR: exit 2, one stderr line naming each of `expected`, no traceback,
    no figure."""
    global cases
    out = os.path.join(directory + "-plots")
    r = subprocess.run([script, directory, "-o", out, "--dpi", "30", *args], capture_output=True, text=True)
    what = f"plot_report.py {directory}: exit {r.returncode}\nstdout: {r.stdout}\nstderr: {r.stderr}"
    assert r.returncode == 2, what
    assert "Traceback" not in r.stderr and r.stderr.count("\n") == 1 and r.stderr.startswith("plot_report.py: "), what
    for text in expected:
        assert text in r.stderr, f"'{text}' not in the message\n{what}"
    cases += 1


def summary(directory):
    return os.path.join(directory, "summary.json")


# summary.json: null, a split that is a number, a key path of the wrong type, nested too deeply.
d = damaged("summary-null", report, lambda d: write(summary(d), "null\n"))
refused(d, f"{summary(d)}: expected a JSON object, found null")
d = damaged("summary-estimation-5", report, lambda d: write(summary(d), '{"estimation":5}'))
refused(d, f"{summary(d)}: estimation: expected an object, found the number 5")
d = damaged("summary-outputs-text", report, lambda d: edit_json(summary(d), lambda s: s["cost"].update(outputs="Tds")))
refused(d, f"{summary(d)}: cost.outputs: expected a list, found the text 'Tds'")
d = damaged("summary-window-label", report,
            lambda d: edit_json(summary(d), lambda s: s["estimation"]["windows"][0].update(window=[1])))
refused(d, f"{summary(d)}: estimation.windows[0].window: expected a text or a number, found a list of 1")
d = damaged("summary-acf-text", report, lambda d: edit_json(
    summary(d), lambda s: s["residual_analysis"]["estimation"]["outputs"]["Tds"].update(acf="white")))
refused(d, f"{summary(d)}: residual_analysis.estimation.outputs.Tds.acf: expected a list, found the text 'white'")
d = damaged("summary-deep", report, lambda d: write(summary(d), '{"cost": ' + "[" * 200000 + "]" * 200000 + "}"))
refused(d, f"{summary(d)}: not a file tvid wrote: JSON nested too deeply")

# The traces: not UTF-8, a renamed column, a short row, a cell that is not a number.
estimation = lambda d: os.path.join(d, "estimation.csv")  # noqa: E731


def latin1(d):
    with open(estimation(d), "rb") as f:
        lines = f.read().split(b"\n")
    lines[3] = lines[3].replace(b",", b",\xe9", 1)
    write(estimation(d), b"\n".join(lines), "wb")


d = damaged("csv-latin1", report, latin1)
refused(d, f"{estimation(d)}:4: not UTF-8 text (byte 0xe9)")


def rename(path, old, new):
    with open(path) as f:
        lines = f.read().split("\n")
    assert old in lines[0].split(","), (path, old, lines[0])
    lines[0] = ",".join(new if cell == old else cell for cell in lines[0].split(","))
    write(path, "\n".join(lines))


d = damaged("csv-renamed-t", report, lambda d: rename(estimation(d), "t [s]", "time [s]"))
refused(d, f"{estimation(d)}: no column t ")
d = damaged("csv-renamed-output", report, lambda d: rename(estimation(d), "Tds_simulated [N m]", "Tds_sim [N m]"))
refused(d, f"{estimation(d)}: no column Tds_simulated ")
history = lambda d: os.path.join(d, "history.csv")  # noqa: E731
d = damaged("csv-renamed-history", report, lambda d: rename(history(d), "best_cost", "best"))
refused(d, f"{history(d)}: no column best_cost ")
spectra = lambda d: os.path.join(d, "spectra.csv")  # noqa: E731
d = damaged("csv-renamed-spectra", report, lambda d: rename(spectra(d), "Tds_residual_psd [(N m)^2/Hz]", "r [1]"))
refused(d, f"{spectra(d)}: no column Tds_residual_psd ")
d = damaged("csv-short-row", report, lambda d: write(estimation(d), "1,2\n", "a"))
refused(d, f"{estimation(d)}:", "2 cells, the header has")


def word_in_row(d):
    with open(estimation(d)) as f:
        lines = f.read().split("\n")
    cells = lines[5].split(",")
    cells[-1] = "fast"
    lines[5] = ",".join(cells)
    write(estimation(d), "\n".join(lines))


d = damaged("csv-word", report, word_in_row)
refused(d, f"{estimation(d)}:6: column ", "'fast' is not a number")

# The sensitivity run: a renamed column, a ranking of the wrong type.
sensitivity = lambda d: os.path.join(d, "sensitivity")  # noqa: E731
d = damaged("sensitivity-renamed", report, lambda d: rename(os.path.join(sensitivity(d), "sensitivity.csv"),
                                                             "window", "win"))
refused(d, f"{os.path.join(sensitivity(d), 'sensitivity.csv')}: no column window ")
d = damaged("sensitivity-ranking", report, lambda d: edit_json(os.path.join(sensitivity(d), "sensitivity.json"),
                                                              lambda s: s["ranking"].update(Tds=[{"rank": 1}])))
refused(d, f"{os.path.join(sensitivity(d), 'sensitivity.json')}: ranking.Tds[0].parameter: missing")

# modes.json: a mode without its fields, a frequency that is text.
modes_json = lambda d: os.path.join(d, "modes.json")  # noqa: E731
d = damaged("modes-empty-mode", modes, lambda d: write(modes_json(d), '{"modes":[{}]}'))
refused(d, f"{modes_json(d)}: modes[0].kind: missing")
d = damaged("modes-text", modes, lambda d: edit_json(modes_json(d), lambda m: m["modes"][-1].update(frequency_hz="x")))
refused(d, f"{modes_json(d)}: modes[", "].frequency_hz: expected a number, found the text 'x'")

# frf: a renamed column, `measured` that is not an object.
d = damaged("frf-renamed", frf, lambda d: rename(os.path.join(d, "frf.csv"), "coherence", "gamma2"))
refused(d, f"{os.path.join(d, 'frf.csv')}: no column coherence ")
d = damaged("frf-measured", frf, lambda d: edit_json(os.path.join(d, "frf.json"), lambda f: f.update(measured=True)))
refused(d, f"{os.path.join(d, 'frf.json')}: measured: expected an object, found true")

# profile.json: interval95 null, a renamed column in profile.csv.
profile_json = lambda d: os.path.join(d, "profile.json")  # noqa: E731
d = damaged("profile-interval-null", profile, lambda d: edit_json(profile_json(d), lambda p: p.update(interval95=None)))
refused(d, f"{profile_json(d)}: interval95: expected an object, found null")
d = damaged("profile-only-interval-null", profile, lambda d: write(profile_json(d), '{"interval95":null}'))
refused(d, f"{profile_json(d)}: interval95: expected an object, found null")
d = damaged("profile-renamed", profile, lambda d: rename(os.path.join(d, "profile.csv"), "delta_chi2", "dchi2"))
refused(d, f"{os.path.join(d, 'profile.csv')}: no column delta_chi2 ")

# The command line and the output place: one line too.
refused(report, "--dpi 0", args=("--dpi", "0"))
refused(report, "unrecognized arguments: --colour", args=("--colour",))
d = damaged("figure-is-a-folder", report, lambda d: os.makedirs(os.path.join(d + "-plots", "fit.png")))
refused(d, os.path.join(d + "-plots", "fit.png"), "not a regular file")


# A real report whose output is named w/motor: drawn, with safe figure names, nothing
# written outside the output folder. Made by tvid from an experiment naming the output
# so; if tvid refuses such a name, by renaming the output of the report above.
def renamed_output(d):
    for folder, _, files in os.walk(d):
        for name in files:
            path = os.path.join(folder, name)
            with open(path) as f:
                text = f.read()
            write(path, text.replace("Tds", "w/motor"))


motor = os.path.join(work_dir, "motor")
motor_yaml = os.path.join(work_dir, "motor.yaml")
with open(config) as f:
    text = f.read()
assert "outputs: { Tds: Tds }" in text
write(motor_yaml, text.replace("outputs: { Tds: Tds }", 'outputs: { "w/motor": Tds }')
      .replace("file: ", f"file: {os.path.join(source_dir, 'configs')}/", 1))
fit = subprocess.run([tvid, "fit", motor_yaml, "-o", motor, "--optimizer", "lm", "--set", "estimation.cost=l2",
                      "--quiet"], capture_output=True, text=True)
if fit.returncode == 0:
    run(tvid, "sensitivity", motor_yaml, "--params", os.path.join(motor, "params.json"), "-o",
        os.path.join(motor, "sensitivity"), "--quiet")
else:
    assert fit.returncode == 2, (fit.returncode, fit.stderr)  # the name refused: rename a report's output instead
    shutil.rmtree(motor, ignore_errors=True)
    damaged("motor", report, renamed_output)
with open(os.path.join(motor, "sensitivity", "sensitivity.json")) as f:
    assert "w/motor" in json.load(f)["outputs"]
out = os.path.join(work_dir, "motor-plots")
r = subprocess.run([script, motor, "-o", out, "--dpi", "30"], capture_output=True, text=True)
assert r.returncode == 0 and "Traceback" not in r.stderr, (r.returncode, r.stderr)
written = r.stdout.split()
assert os.path.join(out, "sensitivity_w_motor.png") in written, written
for path in written:
    assert os.path.dirname(path) == out and os.path.isfile(path), path
assert sorted(os.listdir(out)) == sorted(os.path.basename(p) for p in written), os.listdir(out)
assert not os.path.exists(os.path.join(out, "sensitivity_w")), "a folder was made from the output's name"

print(f"plot_report.py: {cases} damaged inputs refused in one line with exit 2; an output named w/motor drawn as "
      "sensitivity_w_motor.png")
