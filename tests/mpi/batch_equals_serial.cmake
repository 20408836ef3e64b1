# `mpirun -n 2 tvid batch` writes the single process's batch.csv (apart from the wall-time
# column) with the same exit status and job counts, and batch_summary.json records 2
# processes; then, after an interruption (batch.csv cut to its first row), `--resume`
# under mpirun completes the same table.
#   cmake -DTVID=... -DMPIEXEC=... -DMPIEXEC_NUMPROC_FLAG=... -DEXPERIMENT=... -DWORK_DIR=...
#         -DBATCH_ARGS=a|b -DEXPECTED_STATUS=0 [-DCVT_DATA=dir] -P batch_equals_serial.cmake
# With CVT_DATA the jobs are three recordings: the noisy and the clean tip-in and a copy
# of the clean one with a time stamp that is no number (a bad_input row, exit status 1).
include(${CMAKE_CURRENT_LIST_DIR}/mpirun.cmake)
string(REPLACE "|" ";" batch_args "${BATCH_ARGS}")
file(REMOVE_RECURSE "${WORK_DIR}")

if(CVT_DATA)
  file(MAKE_DIRECTORY "${WORK_DIR}/recordings")
  file(COPY_FILE "${CVT_DATA}/tipin_a.csv" "${WORK_DIR}/recordings/noisy.csv")
  file(COPY_FILE "${CVT_DATA}/tipin_clean.csv" "${WORK_DIR}/recordings/clean.csv")
  file(READ "${CVT_DATA}/tipin_clean.csv" clean)
  string(REPLACE "\n1.01," "\nn/a," broken "${clean}")
  file(WRITE "${WORK_DIR}/recordings/broken.csv" "${broken}")
  list(APPEND batch_args --data "${WORK_DIR}/recordings/*.csv")
endif()

# batch.csv with every row's wall time (the last column) blanked.
function(read_table file variable)
  read_required("${file}" text)
  string(REGEX REPLACE ",[0-9.]*\n" ",\n" text "${text}")
  set(${variable} "${text}" PARENT_SCOPE)
endfunction()

run_alone(serial batch "${EXPERIMENT}" -o "${WORK_DIR}/serial" --threads 1 --quiet ${batch_args})
expect_status(serial "${EXPECTED_STATUS}" "tvid batch")
run_mpi(mpi 2 batch "${EXPERIMENT}" -o "${WORK_DIR}/mpi" --threads 1 ${batch_args})
expect_status(mpi "${EXPECTED_STATUS}" "mpirun -n 2 tvid batch")

read_table("${WORK_DIR}/serial/batch.csv" serial_table)
read_table("${WORK_DIR}/mpi/batch.csv" mpi_table)
if(NOT serial_table STREQUAL mpi_table)
  message(FATAL_ERROR "batch.csv differs under mpirun\n--- alone\n${serial_table}\n--- mpirun -n 2\n${mpi_table}")
endif()
string(REGEX MATCHALL "\n" rows "${serial_table}")
list(LENGTH rows lines)
math(EXPR jobs "${lines} - 1")
if(jobs LESS 2)
  message(FATAL_ERROR "expected at least two jobs:\n${serial_table}")
endif()
# Every job's progress line, printed once (by the root).
string(REGEX MATCHALL "\\[[0-9]+/${jobs}\\]" progress "${mpi_err}")
list(LENGTH progress progress_lines)
if(NOT progress_lines EQUAL jobs)
  message(FATAL_ERROR "${progress_lines} progress lines for ${jobs} jobs:\n${mpi_err}")
endif()

read_required("${WORK_DIR}/serial/batch_summary.json" serial_summary)
read_required("${WORK_DIR}/mpi/batch_summary.json" mpi_summary)
foreach(key jobs ok failed bad_input run)
  string(JSON a GET "${serial_summary}" ${key})
  string(JSON b GET "${mpi_summary}" ${key})
  if(NOT a EQUAL b)
    message(FATAL_ERROR "batch_summary.json ${key}: ${a} alone, ${b} under mpirun")
  endif()
endforeach()
string(JSON processes GET "${mpi_summary}" processes)
if(NOT processes EQUAL 2)
  message(FATAL_ERROR "batch_summary.json under mpirun -n 2: processes ${processes}")
endif()

# The interruption: only the header and the first row reached the disk.
read_required("${WORK_DIR}/mpi/batch.csv" text)
string(REGEX MATCH "^[^\n]*\n[^\n]*\n" first "${text}")
file(WRITE "${WORK_DIR}/mpi/batch.csv" "${first}")
file(REMOVE "${WORK_DIR}/mpi/batch_summary.json")
run_mpi(resumed 2 batch "${EXPERIMENT}" -o "${WORK_DIR}/mpi" --threads 1 --quiet --json --resume ${batch_args})
expect_status(resumed "${EXPECTED_STATUS}" "mpirun -n 2 tvid batch --resume")
read_table("${WORK_DIR}/mpi/batch.csv" resumed_table)
if(NOT serial_table STREQUAL resumed_table)
  message(FATAL_ERROR "batch.csv after --resume under mpirun\n--- alone\n${serial_table}\n--- resumed\n${resumed_table}")
endif()
string(JSON run GET "${resumed_out}" run)
math(EXPR expected_run "${jobs} - 1")
if(NOT run EQUAL expected_run)
  message(FATAL_ERROR "--resume ran ${run} jobs, expected ${expected_run}")
endif()
message(STATUS "${jobs} jobs: equal tables alone, under mpirun -n 2, and resumed")
