# What makes the build fast on two cores: unity batches and light optimization
# where nothing is timed.
#
# Unity builds: most of a file's compile time is g++ parsing, and generating,
# again in every file, the same headers and inline code of Ceres, Eigen,
# Boost.Math, CLI11, fmt, nlohmann-json and gtest (four fit/ files compile in
# half the CPU time as one batch). sglab_unity_build(TARGET
# [BATCHES N]): TARGET's files compile as N unity batches (CMake's
# UNITY_BUILD; default 1, the whole target in one file), so a name at file
# scope (an anonymous namespace's too) must be unique within its target. The
# libraries and the command are one batch each: the build compiles them side by
# side, so fewer batches cost less CPU at no loss of parallelism (fit/, g++ 12,
# idle: 65 CPU s as one batch, 72 as two, 80 as three). The tests, compiled
# last, are two, one per core of the machines sglab targets (the 43 test files:
# 122 CPU s as two batches, 142 as three, 167 as four, 180 as six). With one
# batch per target a precompiled header would be parsed once anyway, so there
# is none.
# SGLAB_UNITY=OFF compiles every file on its own (what an editor or clang-tidy
# sees).
option(SGLAB_UNITY "Compile each target's files in unity batches" ON)
function(sglab_unity_build target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "BATCHES" "")
  if(NOT arg_BATCHES)
    set(arg_BATCHES 1)
  endif()
  if(SGLAB_UNITY)
    get_target_property(sources ${target} SOURCES)
    list(FILTER sources INCLUDE REGEX "\\.cpp$")
    list(LENGTH sources n)
    math(EXPR size "(${n} + ${arg_BATCHES} - 1) / ${arg_BATCHES}")
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${size})
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
