// fit/solver_log.hpp — Ceres reports through glog; a library's log is not
// sglab's output. `sglab` initializes glog once, in main, through
// init_solver_logging: glog then writes no log file and prints nothing
// itself, and every message of severity WARNING or above is handed to
// sglab's diagnostics: counted (solver_messages(), which `sglab fit` puts in
// its report) and shown as the note of the fit's progress line, which is
// drawn only when stderr is a terminal (quiet when piped).
#pragma once

#include <cstddef>
#include <string>

namespace sglab::fit {

// Idempotent and thread-safe; `program` is argv[0].
void init_solver_logging(const char* program);

struct SolverMessages {
  std::size_t count = 0;  // messages of severity WARNING or above so far in this process
  std::string last;       // the latest one (its first line), empty when none
};
SolverMessages solver_messages();
// The messages logged on the calling thread (a fit's, when it runs there).
SolverMessages solver_messages_on_this_thread();

}  // namespace sglab::fit
