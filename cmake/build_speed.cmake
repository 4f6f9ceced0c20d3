# What makes the build fast on two cores: precompiled headers and unity batches.
#
# Precompiled headers: the third-party headers that most translation units
# include cost 1-3 s each to parse (nlohmann/json.hpp 2.2 s, Ceres 2.2 s,
# Boost.Math's quadrature 2.1 s, gtest 1.6 s, CLI11 3.4 s of g++ 12 CPU), paid
# again in every file. With unity batches (below) a target parses them once per
# batch, and a precompiled header pays only where it is shared by enough of
# them: measured with g++ 12 (CPU s, the header's own build included), it saves
# in the command (117 against 122) and report/ (48 against 54) and costs more
# than it saves in every other library (common/ 12.5 against 8.8, fit/ 86
# against 80, reference/, validate/, cost/, export/, envmap/ 1.5-7 more), so
# only those two precompile theirs; g++ includes it first in each of their
# files. SGLAB_PCH=OFF builds without them (every file then compiles on its
# own includes alone).
option(SGLAB_PCH "Precompile the heavy third-party headers of the command and report/" ON)

# Included by every target's precompiled header.
set(SGLAB_PCH_COMMON
  <algorithm> <cmath> <cstdint> <filesystem> <functional> <map> <memory> <optional> <set>
  <sstream> <string> <string_view> <vector>
  <fmt/format.h> <nlohmann/json.hpp>)

# sglab_precompile_headers(TARGET [HEADER...]): TARGET's files are compiled
# with a precompiled header of SGLAB_PCH_COMMON and the HEADERs (<...> form).
function(sglab_precompile_headers target)
  if(SGLAB_PCH)
    target_precompile_headers(${target} PRIVATE ${SGLAB_PCH_COMMON} ${ARGN})
  endif()
endfunction()

# Unity builds: even with the headers precompiled, most of a file's compile time
# is g++ generating, again in every file, the same inline code of Ceres, Eigen,
# CLI11, fmt, nlohmann-json and gtest (four fit/ files compile in half the CPU
# time as one batch). sglab_unity_build(TARGET): TARGET's files compile as
# unity batches of SGLAB_UNITY_BATCH files each (CMake's UNITY_BUILD), so a
# name at file scope (an anonymous namespace's too) must be unique within its
# library. SGLAB_UNITY=OFF compiles every file on its own (what an editor or
# clang-tidy sees).
option(SGLAB_UNITY "Compile each target's files in unity batches" ON)
set(SGLAB_UNITY_BATCH 8 CACHE STRING "Files per unity batch")
function(sglab_unity_build target)
  if(SGLAB_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${SGLAB_UNITY_BATCH})
  endif()
endfunction()

# Optimization where it pays: the libraries and the command keep the build
# type's -O3 (their loops are what sglab times and fits with), while the tests'
# own code checks results and calls into the libraries for the heavy work. At
# -O1 g++ 12 compiles a batch of eight test files in 0.64 of its -O3 CPU time
# (41 against 65 s), and the whole suite ran in no more CPU time. An inline
# function that a test file and a library both emit may run as the test's -O1
# copy inside sglab_tests: slower, never different (no -O level changes
# floating-point semantics here: no -ffast-math, and x86-64 has no excess
# precision). sglab_light_optimization(TARGET): TARGET's own files compile at
# -O1 in Release; SGLAB_LIGHT_OPT=OFF keeps -O3.
option(SGLAB_LIGHT_OPT "Compile the tests' own files at -O1 in Release" ON)
function(sglab_light_optimization target)
  if(SGLAB_LIGHT_OPT)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  endif()
endfunction()
