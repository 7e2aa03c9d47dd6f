# A strata program exports no symbol a shared library could bind to: its dynamic symbol table
# holds only what the linker itself defines. (Eigen kernels exported by `strata` were once
# called by gmsh in place of its own, and crashed.) Run with -DEXE=<program>.
execute_process(COMMAND nm -D --defined-only ${EXE} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm -D ${EXE} failed (${rc})")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(exported "")
foreach(line ${lines})
  string(REGEX REPLACE "^[0-9a-fA-F]* *[A-Za-z] " "" sym "${line}")
  # the linker's own markers of the program's layout
  if(sym MATCHES "^(_IO_stdin_used|__bss_start|_edata|_end|__data_start|data_start|_init|_fini|__dso_handle)$" OR sym STREQUAL "")
    continue()
  endif()
  list(APPEND exported "${sym}")
endforeach()
list(LENGTH exported n)
if(n GREATER 0)
  list(SUBLIST exported 0 20 first)
  string(REPLACE ";" "\n  " first "${first}")
  message(FATAL_ERROR "${EXE} exports ${n} symbols, e.g.\n  ${first}")
endif()
message(STATUS "${EXE}: no exported symbols")
