# Helpers of the MPI tests (cmake -P scripts): run tvid alone and under the MPI launcher.
# Expects -DTVID=... -DMPIEXEC=... -DMPIEXEC_NUMPROC_FLAG=... [-DMPIEXEC_PREFLAGS=a|b].
#
# Open MPI's settings for CI: root may launch (CI containers run as root), more processes
# than cores may be started (a 1-core runner), no notice from mpirun when a process exits
# non-zero (tvid's own error line is the whole output), and no cross-memory attach between
# processes (refused in containers without ptrace rights). Other MPI libraries ignore these.
set(ENV{OMPI_ALLOW_RUN_AS_ROOT} 1)
set(ENV{OMPI_ALLOW_RUN_AS_ROOT_CONFIRM} 1)
set(ENV{OMPI_MCA_rmaps_base_oversubscribe} 1)
set(ENV{OMPI_MCA_orte_execute_quiet} 1)
set(ENV{OMPI_MCA_btl_vader_single_copy_mechanism} none)
string(REPLACE "|" ";" mpiexec_preflags "${MPIEXEC_PREFLAGS}")

# tvid ARGS... alone; sets <prefix>_status, <prefix>_out, <prefix>_err.
function(run_alone prefix)
  execute_process(COMMAND "${TVID}" ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 600)
  set(${prefix}_status "${status}" PARENT_SCOPE)
  set(${prefix}_out "${out}" PARENT_SCOPE)
  set(${prefix}_err "${err}" PARENT_SCOPE)
endfunction()

# mpirun -n PROCESSES tvid ARGS...; the same variables. A hang fails the test after 600 s
# (status "Process terminated due to timeout").
function(run_mpi prefix processes)
  execute_process(COMMAND "${MPIEXEC}" ${MPIEXEC_NUMPROC_FLAG} ${processes} ${mpiexec_preflags} "${TVID}" ${ARGN}
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
  set(${prefix}_status "${status}" PARENT_SCOPE)
  set(${prefix}_out "${out}" PARENT_SCOPE)
  set(${prefix}_err "${err}" PARENT_SCOPE)
endfunction()

function(expect_status prefix expected what)
  if(NOT "${${prefix}_status}" STREQUAL "${expected}")
    message(FATAL_ERROR "${what}: exit status ${${prefix}_status}, expected ${expected}\nstdout:\n${${prefix}_out}\nstderr:\n${${prefix}_err}")
  endif()
endfunction()

# The content of a text file, or a failure naming it.
function(read_required file variable)
  if(NOT EXISTS "${file}")
    message(FATAL_ERROR "missing: ${file}")
  endif()
  file(READ "${file}" text)
  set(${variable} "${text}" PARENT_SCOPE)
endfunction()

function(expect_equal_files a b what)
  read_required("${a}" text_a)
  read_required("${b}" text_b)
  if(NOT text_a STREQUAL text_b)
    message(FATAL_ERROR "${what}: ${a} and ${b} differ\n--- ${a}\n${text_a}\n--- ${b}\n${text_b}")
  endif()
endfunction()
