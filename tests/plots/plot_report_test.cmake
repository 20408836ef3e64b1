# scripts/plot_report.py on real output directories of every kind it draws: a fast fit
# (least squares on the noise-free CVT recording, < 1 s), its sensitivity run, its modes
# and frequency response, a profile,
# a short engine fit (2 LM steps; drawn against the crank angle), a multistart fit of
# 4 short starts and a batch. Every file the script names must be a PNG, and the figures
# of each kind must be among them.
# Called by ctest with -DTVID=... -DSOURCE_DIR=... -DWORK_DIR=... -DPYTHON=/usr/bin/python3.
# Without matplotlib the test prints SKIPPED (ctest then reports it as skipped, not passed).

execute_process(COMMAND ${PYTHON} -c "import matplotlib" RESULT_VARIABLE no_matplotlib OUTPUT_QUIET ERROR_QUIET)
if(no_matplotlib)
  message("SKIPPED: ${PYTHON} cannot import matplotlib (Debian: apt-get install python3-matplotlib)")
  return()
endif()

file(REMOVE_RECURSE ${WORK_DIR})
set(report ${WORK_DIR}/report)
set(cvt ${SOURCE_DIR}/configs/cvt_tipin_clean.yaml)
set(engine ${SOURCE_DIR}/configs/engine_idle.yaml)
set(script ${SOURCE_DIR}/scripts/plot_report.py)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# plot_report.py DIR ARGS...: every path it prints must be a PNG; each of `expected` (a list
# of names) must be among them.
set(figures 0)
function(plot what dir expected)
  run("plot_report.py ${what}" ${PYTHON} ${script} ${dir} ${ARGN})
  string(REGEX MATCHALL "[^\n]+\\.png" written "${run_output}")
  foreach(name ${expected})
    if(NOT written MATCHES "/${name}\\.png")
      message(FATAL_ERROR "plot_report.py ${what}: ${name}.png was not written; it wrote:\n${run_output}")
    endif()
  endforeach()
  foreach(png ${written})
    if(NOT EXISTS ${png})
      message(FATAL_ERROR "${png} was named but not written")
    endif()
    file(SIZE ${png} size)
    file(READ ${png} signature LIMIT 8 HEX)
    if(size LESS 1000 OR NOT signature STREQUAL "89504e470d0a1a0a")
      message(FATAL_ERROR "${png} is not a PNG image (${size} bytes, starts with ${signature})")
    endif()
    math(EXPR figures "${figures} + 1")
  endforeach()
  set(figures ${figures} PARENT_SCOPE)
  set(plot_output "${run_output}" PARENT_SCOPE)
endfunction()

# A fit report (its spectra too) and its sensitivity run.
run("tvid fit" ${TVID} fit ${cvt} -o ${report} --optimizer lm --set estimation.cost=l2 --quiet)
run("tvid sensitivity" ${TVID} sensitivity ${cvt} --params ${report}/params.json -o ${WORK_DIR}/sens --quiet)
plot("fit" ${report} "fit;residual;residual_ratio;residual_analysis;cost_history;spectra;sensitivity_Tds;sensitivity_ranking"
     -o ${WORK_DIR}/plots --sensitivity ${WORK_DIR}/sens --dpi 50)

# The fitted model's modes and its frequency response from the input torque to the
# driveshaft torque, beside the measured H1.
run("tvid modes" ${TVID} modes ${cvt} --params ${report}/params.json -o ${WORK_DIR}/modes --quiet)
plot("modes" ${WORK_DIR}/modes "modes" -o ${WORK_DIR}/modes-plots --dpi 50)
run("tvid frf" ${TVID} frf ${cvt} --params ${report}/params.json --input Ttm --output Tds -o ${WORK_DIR}/frf --quiet)
plot("frf" ${WORK_DIR}/frf "frf" -o ${WORK_DIR}/frf-plots --dpi 50)

# A profile.
run("tvid profile" ${TVID} profile ${cvt} --param d_ds --points 5 -o ${WORK_DIR}/profile
    --set estimation.optimizer=lm --set estimation.cost=l2 --set parameters.rho1=1.42855 --quiet)
plot("profile" ${WORK_DIR}/profile "profile" -o ${WORK_DIR}/plots --dpi 50)

# An engine fit, cut to 2 LM steps: its traces carry the crank angle, and cycle 2 (the
# estimation window) begins at 2 x 720 deg of the recording's angle, which starts at 0.
run("tvid fit engine" ${TVID} fit ${engine} -o ${WORK_DIR}/engine --set estimation.lm.max_iterations=2 --quiet)
file(STRINGS ${WORK_DIR}/engine/estimation.csv engine_rows LIMIT_COUNT 2)
list(GET engine_rows 0 engine_header)
list(GET engine_rows 1 engine_first)
if(NOT engine_header MATCHES ",crank_deg \\[deg\\]$" OR NOT engine_first MATCHES ",cycle 2,.*,1440(\\.0*[0-9]?)?$")
  message(FATAL_ERROR "engine estimation.csv: expected crank_deg last, 1440 deg at the start of cycle 2:\n"
                      "${engine_header}\n${engine_first}")
endif()
plot("engine" ${WORK_DIR}/engine "fit;residual;residual_ratio;residual_analysis;cost_history" -o ${WORK_DIR}/engine-plots --dpi 50)

# A multistart fit: 4 starts of 8 LM steps.
run("tvid fit multistart" ${TVID} fit ${cvt} -o ${WORK_DIR}/multistart --optimizer multistart
    --set estimation.cost=l2 --set estimation.multistart.starts=4 --set estimation.multistart.max_iterations=8 --quiet)
plot("multistart" ${WORK_DIR}/multistart "multistart;fit" -o ${WORK_DIR}/multistart-plots --dpi 50)

# A batch directory: least squares on the two CVT recordings, validated on each other
# (--cross): the cross-matrix heatmap and the parameter spread.
run("tvid batch" ${TVID} batch ${cvt} --data ${SOURCE_DIR}/data/cvt/tipin_clean.csv
    --data ${SOURCE_DIR}/data/cvt/tipin_a.csv --cross -o ${WORK_DIR}/batch
    --set estimation.optimizer=lm --set estimation.cost=l2 --quiet)
plot("batch" ${WORK_DIR}/batch "cross_matrix;parameter_spread" -o ${WORK_DIR}/batch-plots --dpi 50)

# A cut-off modes.json: one error line naming the file and line, exit 2, never a traceback.
file(MAKE_DIRECTORY ${WORK_DIR}/broken-modes)
file(WRITE ${WORK_DIR}/broken-modes/modes.json "{\"modes\": [\n")
execute_process(COMMAND ${PYTHON} ${script} ${WORK_DIR}/broken-modes
  RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT status EQUAL 2 OR NOT err MATCHES "broken-modes/modes.json:2: not valid JSON" OR err MATCHES "Traceback")
  message(FATAL_ERROR "plot_report.py on a cut-off modes.json: exit ${status}, '${err}'")
endif()

# Not an output directory: one error line naming the missing file, exit 2, no figure.
file(MAKE_DIRECTORY ${WORK_DIR}/empty)
execute_process(COMMAND ${PYTHON} ${script} ${WORK_DIR}/empty
  RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT status EQUAL 2 OR NOT err MATCHES "summary.json: not found")
  message(FATAL_ERROR "plot_report.py on an empty folder: exit ${status}, '${err}'")
endif()
if(EXISTS ${WORK_DIR}/empty/plots)
  message(FATAL_ERROR "plot_report.py made a plots folder for an empty folder")
endif()
message("plot_report.py: ${figures} PNG figures from ${WORK_DIR}")
