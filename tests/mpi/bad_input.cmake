# Bad input under mpirun: one error line (from the root, not one per process), exit status
# 2, nothing written, and no process left waiting: a file every process finds bad, and an
# output directory only the root looks at (a report or batch already there).
#   cmake -DTVID=... -DMPIEXEC=... -DMPIEXEC_NUMPROC_FLAG=... -DSOURCE_DIR=... -DWORK_DIR=... -P bad_input.cmake
include(${CMAKE_CURRENT_LIST_DIR}/mpirun.cmake)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(expect_one_error_line prefix pattern what)
  expect_status(${prefix} 2 "${what}")
  string(REGEX MATCHALL "\n" lines "${${prefix}_err}")
  list(LENGTH lines count)
  if(NOT count EQUAL 1 OR NOT "${${prefix}_err}" MATCHES "${pattern}")
    message(FATAL_ERROR "${what}: expected one error line matching '${pattern}', got:\n${${prefix}_err}")
  endif()
  if(NOT "${${prefix}_out}" STREQUAL "")
    message(FATAL_ERROR "${what}: printed on stdout:\n${${prefix}_out}")
  endif()
endfunction()

# An experiment with a bound the wrong way round.
file(READ "${SOURCE_DIR}/configs/cvt_tipin_clean.yaml" config)
string(REPLACE "../data/" "${SOURCE_DIR}/data/" config "${config}")
string(REGEX REPLACE "min: [0-9.]+, +max: " "min: 1000, max: " bad "${config}")
if(bad STREQUAL config)
  message(FATAL_ERROR "the test could not break ${SOURCE_DIR}/configs/cvt_tipin_clean.yaml")
endif()
file(WRITE "${WORK_DIR}/bad.yaml" "${bad}")
run_mpi(fit 2 fit "${WORK_DIR}/bad.yaml" -o "${WORK_DIR}/fit")
expect_one_error_line(fit "bad\\.yaml:[0-9]+: parameters\\." "mpirun -n 2 tvid fit bad.yaml")
run_mpi(batch 2 batch "${WORK_DIR}/bad.yaml" -o "${WORK_DIR}/batch" --data "${SOURCE_DIR}/data/cvt/tipin_clean.csv")
expect_one_error_line(batch "bad\\.yaml:[0-9]+: parameters\\." "mpirun -n 2 tvid batch bad.yaml")
if(EXISTS "${WORK_DIR}/fit" OR EXISTS "${WORK_DIR}/batch/batch.csv")
  message(FATAL_ERROR "bad input under mpirun wrote a report")
endif()

# Only the root checks the output directory: the others have loaded the experiment and
# wait for it, and must be told to stop.
file(WRITE "${WORK_DIR}/good.yaml" "${config}")
file(WRITE "${WORK_DIR}/taken/summary.json" "{}\n")
run_mpi(taken 2 fit "${WORK_DIR}/good.yaml" -o "${WORK_DIR}/taken" --set estimation.pso.iterations=1)
expect_one_error_line(taken "taken" "mpirun -n 2 tvid fit into a report directory already used")
file(WRITE "${WORK_DIR}/batch-taken/batch.csv" "id,status\n")
run_mpi(batch_taken 2 batch "${WORK_DIR}/good.yaml" -o "${WORK_DIR}/batch-taken"
        --data "${SOURCE_DIR}/data/cvt/tipin_clean.csv")
expect_one_error_line(batch_taken "--resume" "mpirun -n 2 tvid batch into a batch directory already used")
read_required("${WORK_DIR}/batch-taken/batch.csv" kept)
if(NOT kept STREQUAL "id,status\n")
  message(FATAL_ERROR "the refused batch changed batch.csv:\n${kept}")
endif()
message(STATUS "bad input under mpirun: one line, exit status 2, every process ended")
