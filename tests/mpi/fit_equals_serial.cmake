# `mpirun -n PROCESSES tvid fit --threads MPI_THREADS` gives the report of one process on
# one thread: params.json, params.csv, history.csv and the traces byte for byte, the same
# cost and simulations in summary.json, which records the processes that scored swarm
# candidates (PROCESSES_RECORDED; Levenberg–Marquardt runs on the root alone: 1).
#   cmake -DTVID=... -DMPIEXEC=... -DMPIEXEC_NUMPROC_FLAG=... -DEXPERIMENT=... -DWORK_DIR=...
#         -DFIT_ARGS=a|b -DPROCESSES=2 -DMPI_THREADS=1 -DPROCESSES_RECORDED=2 -P fit_equals_serial.cmake
include(${CMAKE_CURRENT_LIST_DIR}/mpirun.cmake)
string(REPLACE "|" ";" fit_args "${FIT_ARGS}")
file(REMOVE_RECURSE "${WORK_DIR}")

run_alone(serial fit "${EXPERIMENT}" -o "${WORK_DIR}/serial" --threads 1 --quiet ${fit_args})
expect_status(serial 0 "tvid fit")
run_mpi(mpi ${PROCESSES} fit "${EXPERIMENT}" -o "${WORK_DIR}/mpi" --threads ${MPI_THREADS} --json ${fit_args})
expect_status(mpi 0 "mpirun -n ${PROCESSES} tvid fit")

foreach(file params.json params.csv history.csv estimation.csv validation.csv)
  expect_equal_files("${WORK_DIR}/serial/${file}" "${WORK_DIR}/mpi/${file}" "mpirun -n ${PROCESSES} tvid fit")
endforeach()

read_required("${WORK_DIR}/serial/summary.json" serial_summary)
read_required("${WORK_DIR}/mpi/summary.json" mpi_summary)
# --json printed summary.json once, from the root, with the report's directory added.
string(JSON printed_report ERROR_VARIABLE no_report GET "${mpi_out}" report)
if(no_report OR NOT printed_report STREQUAL "${WORK_DIR}/mpi")
  message(FATAL_ERROR "the printed summary names report '${printed_report}', not ${WORK_DIR}/mpi:\n${mpi_out}")
endif()
string(JSON printed_summary REMOVE "${mpi_out}" report)
string(JSON stored_summary SET "${mpi_summary}" report "null")  # the same serializer on both sides
string(JSON stored_summary REMOVE "${stored_summary}" report)
if(NOT stored_summary STREQUAL printed_summary)
  message(FATAL_ERROR "the printed summary differs from summary.json:\n${mpi_out}")
endif()
string(JSON serial_cost GET "${serial_summary}" cost value)
string(JSON mpi_cost GET "${mpi_summary}" cost value)
string(JSON serial_evaluations GET "${serial_summary}" optimizer evaluations)
string(JSON mpi_evaluations GET "${mpi_summary}" optimizer evaluations)
string(JSON serial_processes GET "${serial_summary}" processes)
string(JSON mpi_processes GET "${mpi_summary}" processes)
if(NOT serial_cost STREQUAL mpi_cost OR NOT serial_evaluations STREQUAL mpi_evaluations)
  message(FATAL_ERROR "cost ${serial_cost} / ${mpi_cost}, evaluations ${serial_evaluations} / ${mpi_evaluations}")
endif()
# The work: every process's right-hand sides summed on the root, the same as one process's.
string(JSON serial_rhs GET "${serial_summary}" optimizer right_hand_sides)
string(JSON mpi_rhs GET "${mpi_summary}" optimizer right_hand_sides)
if(serial_rhs LESS_EQUAL 0 OR NOT serial_rhs EQUAL mpi_rhs)
  message(FATAL_ERROR "right-hand sides ${serial_rhs} alone, ${mpi_rhs} under mpirun")
endif()
if(NOT serial_processes EQUAL 1 OR NOT mpi_processes EQUAL PROCESSES_RECORDED)
  message(FATAL_ERROR "summary.json processes: ${serial_processes} alone, ${mpi_processes} under mpirun "
                      "(expected ${PROCESSES_RECORDED})")
endif()
message(STATUS "equal reports, cost ${mpi_cost}, ${mpi_evaluations} simulations")
