// sglab/version.hpp — the version of sglab, stated once: CMake reads it from
// here (project(VERSION), the installed package's version file) and the tools
// print it (`sglab --version`, the provenance of every constant set).
#pragma once

#define SGLAB_VERSION "0.1.0"
#define SGLAB_VERSION_MAJOR 0
#define SGLAB_VERSION_MINOR 1
#define SGLAB_VERSION_PATCH 0
