// `sglab run`: the main job. Runs every step as its own `sglab` subcommand
// (so each keeps one implementation), logs each into OUT/logs/, and writes
// OUT/index.md showing every table and figure. Constants are refitted into
// OUT/constants so that the main job never rewrites the committed data/.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "io.hpp"

namespace sglab::app {

namespace {

namespace fs = std::filesystem;

struct Step {
  std::string name;
  std::string arguments;  // after `sglab`
  std::string dir;        // output directory under OUT
};

std::string self_path() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("sglab") : p.string();
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The Markdown files a step wrote, inlined; figures linked as images.
std::string section(const fs::path& out, const Step& step, int status, double seconds) {
  std::string md = fmt::format("## {}\n\n`sglab {}` — {} in {:.1f} s (log: `logs/{}.log`)\n\n", step.name,
                               step.arguments, status == 0 ? "ok" : fmt::format("FAILED (exit {})", status), seconds,
                               step.name);
  const fs::path dir = out / step.dir;
  if (!fs::exists(dir)) return md;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const std::string rel = fs::relative(f, out).string();
    if (f.extension() == ".md") {
      md += fmt::format("### {}\n\n{}\n\n", rel, io::read_file(f));
    } else if (f.extension() == ".png") {
      md += fmt::format("![{}]({})\n\n", f.stem().string(), rel);
    }
  }
  return md;
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "The main job: fit all, sweep, erf, stability, claims, bench, pareto, "
                                        "figures into OUT with OUT/index.md");
  auto out = std::make_shared<std::string>("out");
  auto quick = std::make_shared<bool>(false);
  auto skip = std::make_shared<std::vector<std::string>>();
  cmd->add_option("--out", *out, "output directory")->capture_default_str();
  cmd->add_flag("--quick", *quick, "sample the erf check instead of every float");
  cmd->add_option("--skip", *skip, "skip a step by name (repeatable)");
  cmd->callback([out, quick, skip] {
    const fs::path root = *out;
    const std::vector<Step> steps = {
        {"fit", fmt::format("fit all --out {0}/constants --header {0}/constants/constants.hpp", root.string()),
         "constants"},
        {"sweep", fmt::format("sweep --backend auto --out {}/sweep", root.string()), "sweep"},
        {"erf", fmt::format("erf{} --out {}/erf", *quick ? "" : " --exhaustive", root.string()), "erf"},
        {"stability", fmt::format("stability --out {}/stability", root.string()), "stability"},
        {"claims", fmt::format("claims --out {}/claims", root.string()), "claims"},
        {"bench", fmt::format("bench --out {}/bench", root.string()), "bench"},
        {"pareto", fmt::format("pareto --out {}/pareto", root.string()), "pareto"},
        {"figures", fmt::format("figures --out {0}/figures --pareto {0}/pareto/pareto.csv", root.string()),
         "figures"},
    };
    for (const auto& s : *skip) {
      if (std::none_of(steps.begin(), steps.end(), [&](const Step& st) { return st.name == s; }))
        throw InputError(fmt::format("--skip: unknown step '{}'", s));
    }
    fs::create_directories(root / "logs");
    const std::string self = self_path();
    std::string index = "# sglab results\n\nProduced by `sglab run`; every section names the command that made it.\n\n";
    int failures = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Step& step : steps) {
      if (std::find(skip->begin(), skip->end(), step.name) != skip->end()) continue;
      const std::string log = (root / "logs" / (step.name + ".log")).string();
      if (io::stderr_is_terminal()) fmt::print(stderr, "sglab run: {} ...\n", step.name);
      const auto start = std::chrono::steady_clock::now();
      const int raw = std::system(fmt::format("{} {} > {} 2>&1 < /dev/null", shell_quote(self), step.arguments,
                                              shell_quote(log))
                                      .c_str());
      const int status = raw == -1 ? -1 : WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fmt::print("{:<10} {:>7.1f} s  {}\n", step.name, secs, status == 0 ? "ok" : fmt::format("FAILED, see {}", log));
      if (status != 0) ++failures;
      index += section(root, step, status, secs);
    }
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    index += fmt::format("\nTotal: {:.1f} s.\n", total);
    io::write_file_atomic(root / "index.md", index);
    fmt::print("total {:.1f} s; wrote {}\n", total, (root / "index.md").string());
    if (failures) throw std::runtime_error(fmt::format("{} step(s) failed", failures));
  });
}

}  // namespace sglab::app
