# Compile settings shared by every strata target, through one interface target.
add_library(strata_compile_options INTERFACE)
target_compile_features(strata_compile_options INTERFACE cxx_std_20)
target_compile_options(strata_compile_options INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wno-unused-parameter>
  $<$<AND:$<CXX_COMPILER_ID:GNU,Clang>,$<CONFIG:Release>>:-O3>)
if(STRATA_NATIVE)
  target_compile_options(strata_compile_options INTERFACE $<$<CXX_COMPILER_ID:GNU,Clang>:-march=native>)
endif()
# strata's code is linked statically into its programs, and a program must not offer its own
# copies of header-only code (Eigen, fmt, VTK's inline functions, ...) to the shared libraries
# it loads: the dynamic linker would bind a library's calls to them (gmsh calling an Eigen
# kernel strata compiled with -march=native and 64-byte alignment crashed on gmsh's 16-byte
# aligned buffers). Hidden visibility keeps every symbol strata compiles inside its program;
# --exclude-libs does the same for what comes from static archives. tests/install checks
# that `strata` exports nothing.
target_compile_options(strata_compile_options INTERFACE
  "$<BUILD_INTERFACE:$<$<CXX_COMPILER_ID:GNU,Clang>:-fvisibility=hidden;-fvisibility-inlines-hidden>>")
target_link_options(strata_compile_options INTERFACE
  $<BUILD_INTERFACE:$<$<AND:$<CXX_COMPILER_ID:GNU,Clang>,$<PLATFORM_ID:Linux>>:LINKER:--exclude-libs,ALL>>)
# GCC 12's AVX-512 intrinsics warn inside the compiler's own header (see the header).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(strata_compile_options INTERFACE
    $<BUILD_INTERFACE:-include${PROJECT_SOURCE_DIR}/cmake/quiet_intrinsics.hpp>)
endif()
if(STRATA_SANITIZE)
  target_compile_options(strata_compile_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                         -fno-sanitize-recover=undefined)
  target_link_options(strata_compile_options INTERFACE -fsanitize=address,undefined)
endif()
install(TARGETS strata_compile_options EXPORT strataTargets)

# strata_add_library(NAME dem SOURCES ... DEPS ...): target strata_<name>, alias strata::<name>,
# public headers in <dir>/include/strata/<name>/.
function(strata_add_library)
  cmake_parse_arguments(A "" "NAME" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(t strata_${A_NAME})
  if(A_SOURCES)
    add_library(${t} ${A_SOURCES})
    set(scope PUBLIC)
  else()
    add_library(${t} INTERFACE)
    set(scope INTERFACE)
  endif()
  add_library(strata::${A_NAME} ALIAS ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${A_NAME} OUTPUT_NAME strata_${A_NAME})
  target_include_directories(${t} ${scope}
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${t} ${scope} strata_compile_options ${A_PUBLIC_DEPS})
  if(A_PRIVATE_DEPS AND A_SOURCES)
    target_link_libraries(${t} PRIVATE ${A_PRIVATE_DEPS})
  endif()
  install(TARGETS ${t} EXPORT strataTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# strata_unity_build(<target>): compile <target> as a unity build (its sources in batches, each
# batch one compiler run), which parses each header once per batch instead of once per file.
# Every strata library and test executable is built this way. A batch may inline a function
# of one file into another, and where multiply-adds are contracted into FMAs that could in
# principle move the last bits of a result: libdem and preprocess, whose results must agree
# to the bit wherever a kernel is inlined, compile with -ffp-contract=off; for the others
# (scene, fem, couple, cases, io, core, the application) the switch from one file per
# compiler run left the state hash and every reported number of each example's quick scene
# as they were. A source file with compile options of its own (the step kernel, for one) is
# compiled on its own. File-local names must be unique within such a target. (The sanitizer
# and minimal builds of scripts/test set CMAKE_UNITY_BUILD, which covers every target.)
function(strata_unity_build target)
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON)
endfunction()
