# `mpirun -n 2 tvid batch --cross`: the root computes the cross-cycle matrix after the
# jobs, and matrix.csv, matrix_long.csv and parameter_stability.csv equal one process's.
#   cmake -DTVID=... -DMPIEXEC=... -DMPIEXEC_NUMPROC_FLAG=... -DEXPERIMENT=... -DWORK_DIR=...
#         -DBATCH_ARGS=a|b -P batch_cross_equals_serial.cmake
include(${CMAKE_CURRENT_LIST_DIR}/mpirun.cmake)
string(REPLACE "|" ";" batch_args "${BATCH_ARGS}")
file(REMOVE_RECURSE "${WORK_DIR}")

run_alone(serial batch "${EXPERIMENT}" -o "${WORK_DIR}/serial" --threads 1 --quiet --cross ${batch_args})
expect_status(serial 0 "tvid batch --cross")
run_mpi(mpi 2 batch "${EXPERIMENT}" -o "${WORK_DIR}/mpi" --threads 1 --cross ${batch_args})
expect_status(mpi 0 "mpirun -n 2 tvid batch --cross")
foreach(file matrix.csv matrix_long.csv parameter_stability.csv)
  expect_equal_files("${WORK_DIR}/serial/${file}" "${WORK_DIR}/mpi/${file}" "${file} under mpirun")
endforeach()
# One line per fitted job after the header, and the summary printed once, by the root.
read_required("${WORK_DIR}/mpi/matrix.csv" matrix)
string(REGEX MATCHALL "\n" rows "${matrix}")
list(LENGTH rows lines)
if(NOT lines EQUAL 4)
  message(FATAL_ERROR "matrix.csv of three jobs has ${lines} lines:\n${matrix}")
endif()
string(REGEX MATCHALL "cross-validation over 3 jobs" summaries "${mpi_out}")
list(LENGTH summaries printed)
if(NOT printed EQUAL 1)
  message(FATAL_ERROR "the cross-validation line printed ${printed} times:\n${mpi_out}")
endif()
