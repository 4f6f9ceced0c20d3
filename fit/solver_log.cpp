#include "fit/solver_log.hpp"

#include <algorithm>
#include <mutex>

#include <glog/logging.h>

#include "fit/minimax.hpp"

namespace sglab::fit {

namespace {

std::mutex g_mutex;
SolverMessages g_messages;
// The messages logged on this thread: glog hands a message to the sink on
// the thread that logs it, and a fit's solver runs on the fit's thread.
thread_local SolverMessages t_messages;

// glog calls send() with its own locks held: no logging here, only a count,
// the text and the progress note (which draws on a terminal only).
class DiagnosticsSink final : public google::LogSink {
 public:
  void send(google::LogSeverity severity, const char*, const char* base_filename, int line,
            const google::LogMessageTime&, const char* message, std::size_t length) override {
    if (severity < google::GLOG_WARNING) return;
    // its first non-blank line (Ceres starts some with a newline)
    std::string text(message, length);
    text.erase(0, std::min(text.find_first_not_of(" \n"), text.size()));
    if (const auto eol = text.find('\n'); eol != std::string::npos) text.resize(eol);
    text = std::string(base_filename) + ":" + std::to_string(line) + ": " + text;
    {
      const std::lock_guard lock(g_mutex);
      ++g_messages.count;
      g_messages.last = text;
    }
    ++t_messages.count;
    t_messages.last = text;
    fit_progress_note("solver: " + text);
  }
};

}  // namespace

void init_solver_logging(const char* program) {
  static std::once_flag once;
  std::call_once(once, [program] {
    static DiagnosticsSink sink;
    FLAGS_logtostderr = false;
    FLAGS_alsologtostderr = false;
    FLAGS_stderrthreshold = google::GLOG_FATAL;  // a FATAL message still explains the abort
    FLAGS_minloglevel = google::GLOG_WARNING;    // Ceres' INFO and VLOG lines are not built
    google::InitGoogleLogging(program);
    for (google::LogSeverity s = google::GLOG_INFO; s < google::NUM_SEVERITIES; ++s)
      google::SetLogDestination(s, "");  // "" = no log file for this severity
    google::AddLogSink(&sink);
  });
}

SolverMessages solver_messages() {
  const std::lock_guard lock(g_mutex);
  return g_messages;
}

SolverMessages solver_messages_on_this_thread() { return t_messages; }

}  // namespace sglab::fit
