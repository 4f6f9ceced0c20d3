// `sglab run`: the main job. Runs every step as its own `sglab` subcommand, in
// this process (the subcommands' own code, parsed from an argument vector: no
// shell, so any output path works, spaces, quotes and semicolons included),
// logs each into OUT/logs/, and writes OUT/index.md linking every table and
// figure. Constants are refitted into OUT/constants so that the main job never
// rewrites the committed data/.
//
// Everything is written into a fresh staging folder beside OUT
// (OUT.staging-PID-RANDOM), which replaces OUT only when the run has finished
// (io::replace_folder: an atomic exchange of the two folders where the file
// system allows it): an interrupted run leaves the previous OUT as it was,
// never an index.md whose steps and logs disagree. OUT is replaced only when
// it is absent, empty or an earlier run's output whose manifest
// (OUT/sglab-output.json) lists everything in it, and never when it is the
// working folder, the checkout, /, $HOME or the like
// (io::check_replaceable_folder, checked before any step runs). Each log is
// written beside its final name and renamed when its step ends.
//
// OUT/index.md: one H1, one H2 per step, one H3 per Markdown file a step
// wrote. A short Markdown file is inlined with its headings moved below that
// H3 and its relative links rewritten to resolve from OUT; a long one (more
// than kInlineLines lines, e.g. the per-κ sweep table) is linked instead.
// Every figure is shown once.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "cost/cost_table.hpp"

namespace sglab::app {

namespace {

namespace fs = std::filesystem;

// A Markdown file longer than this is linked from index.md, not inlined.
constexpr std::size_t kInlineLines = 120;

// How much of its work a step runs. `sglab run` runs every step in its
// representative form (the same sections, tables and figures, from a sample of
// the full work where the full work is long); `sglab run --full`, which
// scripts/results.sh runs for the committed results, runs the full one;
// `--quick` the smallest sample (the tests).
enum class Form { quick, representative, full };

std::string_view form_name(Form f) {
  switch (f) {
    case Form::quick:
      return "quick";
    case Form::representative:
      return "representative";
    case Form::full:
      return "full";
  }
  return "full";
}

struct Step {
  Step(std::string name_, std::vector<std::string> arguments_, std::string dir_)
      : name(std::move(name_)), arguments(std::move(arguments_)), dir(std::move(dir_)) {}
  std::string name;
  std::vector<std::string> arguments;  // after `sglab`
  std::string dir;                     // output directory under OUT
  // The form these arguments are in, what that form leaves out of the full
  // work (empty in the full form), and the arguments of the full form.
  Form form = Form::full;
  std::string sample;
  std::vector<std::string> full_arguments;
};

// For display only (index.md, the terminal): the arguments quoted so that the
// line can be pasted into a POSIX shell. Nothing is ever run through a shell.
std::string display_command(const std::vector<std::string>& arguments) {
  std::string out = "sglab";
  for (const std::string& a : arguments) {
    const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) ||
             std::string_view("-_./:=+,").find(c) != std::string_view::npos;
    });
    if (plain) {
      out += " " + a;
      continue;
    }
    out += " '";
    for (char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += "'";
  }
  return out;
}

// Standard output and standard error of this process go to `log` while this
// object lives (C stdio and iostreams are flushed on both edges).
class RedirectOutput {
 public:
  explicit RedirectOutput(const fs::path& log) {
    flush();
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
      throw std::runtime_error(
          fmt::format("cannot write {}: {}", log.string(), std::strerror(errno)));
    saved_out_ = ::dup(STDOUT_FILENO);
    saved_err_ = ::dup(STDERR_FILENO);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  ~RedirectOutput() {
    flush();
    if (saved_out_ >= 0) {
      ::dup2(saved_out_, STDOUT_FILENO);
      ::close(saved_out_);
    }
    if (saved_err_ >= 0) {
      ::dup2(saved_err_, STDERR_FILENO);
      ::close(saved_err_);
    }
  }
  RedirectOutput(const RedirectOutput&) = delete;
  RedirectOutput& operator=(const RedirectOutput&) = delete;

 private:
  static void flush() {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(stdout);
    std::fflush(stderr);
  }
  int saved_out_ = -1, saved_err_ = -1;
};

// While a step runs: on a terminal, the line "sglab run [3/11] erf
// (representative) 12 s" redrawn every half second on `tty` (the terminal
// stderr was before the step's output went to its log) and cleared at the
// end; nothing when `tty` is -1 (stderr not a terminal).
class StepTicker {
 public:
  StepTicker(int tty, std::string label) : tty_(tty), label_(std::move(label)) {
    if (tty_ >= 0) thread_ = std::thread([this] { loop(); });
  }
  ~StepTicker() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
    write("\r\033[K");
  }
  StepTicker(const StepTicker&) = delete;
  StepTicker& operator=(const StepTicker&) = delete;

 private:
  void loop() {
    std::unique_lock lock(mutex_);
    do {
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      write(fmt::format("\r{} {:.0f} s\033[K", label_, secs));
    } while (!wake_.wait_for(lock, std::chrono::milliseconds(500), [this] { return stop_; }));
  }
  void write(std::string_view text) const {
    while (!text.empty()) {
      const ssize_t n = ::write(tty_, text.data(), text.size());
      if (n <= 0) return;
      text.remove_prefix(static_cast<std::size_t>(n));
    }
  }
  int tty_;
  std::string label_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

// Runs `sglab ARGUMENTS` in this process with the same exit codes as main():
// 0 success, 1 failure, 2 bad input, CLI11's code for a command-line error.
int run_step(const std::vector<std::string>& arguments) {
  CLI::App app{"sglab"};
  app.require_subcommand(1);
  add_fit_command(app);
  add_sweep_command(app);
  add_erf_command(app);
  add_stability_command(app);
  add_claims_command(app);
  add_bench_command(app);
  add_gpucost_command(app);
  add_pareto_command(app);
  add_figures_command(app);
  add_envmap_command(app);
  // CLI11 takes them last first
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
  return run_and_map_exit_code(app, [&] { app.parse(reversed); });
}

bool is_relative_target(std::string_view t) {
  return !t.empty() && t.front() != '/' && t.front() != '#' &&
         t.find("://") == std::string_view::npos && t.rfind("mailto:", 0) != 0;
}

// `target` (relative to the folder `from`, itself relative to OUT) as a path
// relative to OUT.
std::string rebase(std::string_view target, const fs::path& from) {
  return (from / fs::path(std::string(target))).lexically_normal().generic_string();
}

// What index.md already shows (images) and links to (every target), as paths
// relative to OUT.
struct Seen {
  std::set<std::string> images;
  std::set<std::string> links;
};

// One line of Markdown with every relative link and image target rebased from
// `from` to OUT. An image already shown becomes a plain link, so that each
// figure appears once. Inline code spans are left as they are.
std::string rewrite_links(std::string_view line, const fs::path& from, Seen& seen) {
  std::string out;
  std::size_t i = 0;
  while (i < line.size()) {
    const char ch = line[i];
    if (ch == '`') {  // code span: copy through the closing run of backticks
      std::size_t run = 0;
      while (i + run < line.size() && line[i + run] == '`') ++run;
      const std::string fence(run, '`');
      const std::size_t close = line.find(fence, i + run);
      const std::size_t end = close == std::string_view::npos ? line.size() : close + run;
      out.append(line.substr(i, end - i));
      i = end;
      continue;
    }
    const bool image = ch == '!' && i + 1 < line.size() && line[i + 1] == '[';
    if (ch == '[' || image) {
      const std::size_t open = image ? i + 1 : i;
      std::size_t depth = 0, close = std::string_view::npos;
      for (std::size_t k = open; k < line.size(); ++k) {
        if (line[k] == '[') ++depth;
        if (line[k] == ']' && --depth == 0) {
          close = k;
          break;
        }
      }
      if (close != std::string_view::npos && close + 1 < line.size() && line[close + 1] == '(') {
        const std::size_t paren = line.find(')', close + 2);
        if (paren != std::string_view::npos) {
          const std::string_view text = line.substr(open + 1, close - open - 1);
          std::string_view target = line.substr(close + 2, paren - close - 2);
          std::string_view title;
          if (const std::size_t sp = target.find(' '); sp != std::string_view::npos) {
            title = target.substr(sp);
            target = target.substr(0, sp);
          }
          const std::string rebased =
              is_relative_target(target) ? rebase(target, from) : std::string(target);
          const bool duplicate = image && !seen.images.insert(rebased).second;
          seen.links.insert(rebased);
          out += fmt::format("{}[{}]({}{})", image && !duplicate ? "!" : "", text, rebased, title);
          i = paren + 1;
          continue;
        }
      }
    }
    out += ch;
    ++i;
  }
  return out;
}

// A Markdown file for inlining under an H3: headings moved down three levels
// (H1 → H4, at most H6) and links rebased from `from` to OUT. Fenced code
// blocks are copied unchanged.
std::string inline_markdown(const std::string& text, const fs::path& from, Seen& seen) {
  std::string out;
  bool fenced = false;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    start = end + 1;
    if (line.rfind("```", 0) == 0 || line.rfind("~~~", 0) == 0) fenced = !fenced;
    if (fenced || line.rfind("```", 0) == 0 || line.rfind("~~~", 0) == 0) {
      out.append(line);
      out += '\n';
      continue;
    }
    std::size_t level = 0;
    while (level < line.size() && line[level] == '#') ++level;
    if (level >= 1 && level <= 6 && (level == line.size() || line[level] == ' ')) {
      out += std::string(std::min<std::size_t>(level + 3, 6), '#');
      out += rewrite_links(line.substr(level), from, seen);
    } else {
      out += rewrite_links(line, from, seen);
    }
    out += '\n';
  }
  return out;
}

std::size_t count_lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')) +
         (!s.empty() && s.back() != '\n');
}

// The line of index.md saying which form a step ran in and, unless it was the
// full one, what the full form adds and its command.
std::string form_line(const Step& step) {
  if (step.form == Form::full) return "Form: full.\n\n";
  return fmt::format(
      "Form: {} ({}). Full form (scripts/results.sh runs it, through `sglab run --full`): "
      "`{}`\n\n",
      form_name(step.form), step.sample, display_command(step.full_arguments));
}

// The section of index.md for one step: its command and status, its Markdown
// files (inlined or linked), the figures not shown by them, and links to the
// other files it wrote that those do not link.
std::string section(const fs::path& out, const Step& step, int status, double seconds, Seen& seen) {
  const std::string log = fmt::format("logs/{}.log", step.name);
  std::string md = fmt::format("## {}\n\n`{}` — {} in {:.1f} s (log: [{}]({}))\n\n{}", step.name,
                               display_command(step.arguments),
                               status == 0 ? "ok" : fmt::format("FAILED (exit {})", status),
                               seconds, log, log, form_line(step));
  const fs::path dir = out / step.dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return md;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<std::string> others;
  for (const fs::path& f : files) {
    const std::string rel = fs::relative(f, out).generic_string();
    if (f.filename().string().front() == '.') continue;  // temporaries
    if (f.extension() == ".md") {
      // A step writing into an earlier step's folder (gpucost into bench/)
      // shows only what that step's section did not.
      if (!seen.links.insert(rel).second) continue;
      const std::string text = io::read_file(f);
      const std::size_t lines = count_lines(text);
      if (lines > kInlineLines)
        md += fmt::format("### {}\n\n[{}]({}) ({} lines, linked rather than inlined)\n\n", rel, rel,
                          rel, lines);
      else
        md += fmt::format("### {}\n\n{}\n", rel,
                          inline_markdown(text, fs::relative(f.parent_path(), out), seen));
    }
  }
  for (const fs::path& f : files) {
    const std::string rel = fs::relative(f, out).generic_string();
    if (f.filename().string().front() == '.') continue;
    if (f.extension() == ".png" && seen.images.insert(rel).second) {
      md += fmt::format("![{}]({})\n\n", f.stem().string(), rel);
      seen.links.insert(rel);
    } else if (!seen.links.count(rel)) {
      others.push_back(rel);
    }
  }
  if (!others.empty()) {
    md += "Other files:";
    for (std::size_t i = 0; i < others.size(); ++i)
      md += fmt::format("{} [{}]({})", i ? "," : "", others[i], others[i]);
    md += "\n\n";
  }
  return md;
}

// The steps of the main job writing under `root`, in `form`. pareto reads the
// costs the bench and gpucost steps measured, or the committed table when
// bench is skipped: GPU cost (its default, gpu:navi21) into pareto/, CPU batch
// ns into pareto-cpu/; the figure shows both side by side. A step whose
// sample differs from its full work says what it leaves out (Step::sample).
std::vector<Step> run_steps(const fs::path& root, Form form, bool bench_skipped) {
  const auto in = [&root](const char* sub) { return (root / sub).string(); };
  std::vector<std::string> pareto = {"pareto", "--out", in("pareto")};
  std::vector<std::string> pareto_cpu = {"pareto", "--cost", "cpu-batch", "--out",
                                         in("pareto-cpu")};
  std::vector<std::string> figures = {"figures",
                                      "--out",
                                      in("figures"),
                                      "--pareto",
                                      in("pareto/pareto.csv"),
                                      "--pareto",
                                      in("pareto-cpu/pareto.csv")};
  if (!bench_skipped)
    for (auto* step : {&pareto, &pareto_cpu, &figures})
      step->insert(step->end(), {"--costs", in("bench/costs.json")});
  std::vector<Step> steps = {
      {"fit",
       {"fit", "all", "--out", in("constants"), "--header", in("constants/constants.hpp")},
       "constants"},
      {"sweep", {"sweep", "--backend", "auto", "--out", in("sweep")}, "sweep"},
      {"erf", {"erf", "--exhaustive", "--out", in("erf")}, "erf"},
      {"stability", {"stability", "--out", in("stability")}, "stability"},
      {"claims", {"claims", "--out", in("claims")}, "claims"},
      {"bench", {"bench", "--out", in("bench")}, "bench"},
      // GPU cost into the same cost table (skipped, with the reason, where RADV has no null
      // device), both languages: each export's header states its own (sglab export).
      {"gpucost",
       {"gpucost", "--skip-unavailable", "--lang", "both", "--out", in("bench")},
       "bench"},
      {"pareto", pareto, "pareto"},
      {"pareto-cpu", pareto_cpu, "pareto-cpu"},
      {"figures", figures, "figures"},
      // Probes (SH, ZH3, SG lobes, SH + lobes) on the full maps when blender-data is installed.
      {"envmap", {"envmap", "baselines", "--probes", "--out", in("envmap")}, "envmap"},
  };
  // The smaller forms: the arguments they drop and add, and what they leave
  // out of the full work. A sample serves the runs of its form and of the
  // smaller ones; the first that serves a run is the one taken (so a step's
  // quick sample comes before its representative one).
  struct Sample {
    std::string step;
    Form form;
    std::vector<std::string> drop, add;
    std::string what;
  };
  const std::vector<Sample> samples = {
      {"gpucost",
       Form::quick,
       {"--lang", "both"},
       {"--family", "navi21"},
       "navi21 (the chip of the Pareto chart's cost) in GLSL instead of five chips in GLSL and "
       "HLSL"},
      {"erf",
       Form::representative,
       {"--exhaustive"},
       {},
       "the float check on a dense sample of floats instead of every float"},
      {"bench",
       Form::representative,
       {},
       {"--repetitions", "3", "--min-time", "0.01"},
       "the median of 3 repetitions of 0.01 s per case instead of 5 of 0.05 s: the same "
       "cases, noisier timings"},
      {"envmap",
       Form::representative,
       {},
       {"--quick"},
       "every fourth map at 27 floats instead of every map at 15, 27, 48 and 75 floats"},
  };
  for (Step& step : steps) {
    const auto sample = std::find_if(samples.begin(), samples.end(), [&](const Sample& x) {
      return x.step == step.name && form <= x.form;
    });
    if (sample == samples.end()) continue;
    step.full_arguments = step.arguments;
    std::vector<std::string> a;
    for (const std::string& arg : step.arguments)
      if (std::find(sample->drop.begin(), sample->drop.end(), arg) == sample->drop.end())
        a.push_back(arg);
    a.insert(a.end(), sample->add.begin(), sample->add.end());
    step.arguments = std::move(a);
    step.form = form;
    step.sample = sample->what;
  }
  return steps;
}

// Whether the cost table a pareto step reads (its --costs, else the project's)
// has the GPU costs that its default --cost needs: gpucost writes none where
// RADV has no null device. A missing or malformed table counts as having them,
// so that the step itself reports it.
bool has_gpu_costs(const Step& step) {
  const auto it = std::find(step.arguments.begin(), step.arguments.end(), "--costs");
  std::optional<fs::path> path = cost::default_cost_table_path();
  if (it != step.arguments.end() && it + 1 != step.arguments.end()) path = *(it + 1);
  try {
    const auto table = path ? cost::read_existing_cost_table(*path) : std::nullopt;
    return !table || table->gpu.has_value();
  } catch (const std::exception&) {
    return true;
  }
}

// Runs one step with its output in `log`, written beside it and renamed when
// the step ends (so that a log is never seen half-written).
int run_logged(const Step& step, const fs::path& log) {
  const fs::path partial = log.parent_path() / ("." + log.filename().string() + ".partial");
  int status = 1;
  {
    RedirectOutput redirect(partial);
    status = run_step(step.arguments);
  }
  fs::rename(partial, log);
  return status;
}

// The arguments of this run (after `sglab`), for its manifest.
std::vector<std::string> run_arguments(const fs::path& out, Form form,
                                       const std::vector<std::string>& skip) {
  std::vector<std::string> a = {"run", "--out", out.string()};
  if (form != Form::representative) a.push_back("--" + std::string(form_name(form)));
  for (const std::string& s : skip) a.insert(a.end(), {"--skip", s});
  return a;
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("run",
                         "The main job: fit all, sweep, erf, stability, claims, bench, pareto, "
                         "figures into OUT with OUT/index.md");
  auto out = std::make_shared<std::string>("out");
  auto quick = std::make_shared<bool>(false);
  auto full = std::make_shared<bool>(false);
  auto skip = std::make_shared<std::vector<std::string>>();
  add_path_option(cmd, "--out", *out, "output directory")->capture_default_str();
  auto* full_flag = cmd->add_flag(
      "--full", *full,
      "every step's full work (scripts/results.sh): the exhaustive erf check, long benchmark "
      "repetitions; by default the long steps run a representative sample, each section of "
      "index.md names its form and the full command");
  cmd->add_flag("--quick", *quick,
                "the smallest samples: erf on a dense sample of floats, short benchmark "
                "repetitions, GPU costs on navi21 in GLSL, envmap probes of every fourth map "
                "at 27 floats")
      ->excludes(full_flag);
  cmd->add_option("--skip", *skip, "skip a step by name (repeatable)");
  cmd->callback([out, quick, full, skip] {
    const Form form = *full ? Form::full : *quick ? Form::quick : Form::representative;
    const fs::path root = *out;
    io::check_replaceable_folder(root, "--out");
    const auto skipped = [&skip](const std::string& name) {
      return std::find(skip->begin(), skip->end(), name) != skip->end();
    };
    const std::vector<Step> shown = run_steps(root, form, skipped("bench"));
    for (const auto& s : *skip) {
      if (std::none_of(shown.begin(), shown.end(), [&](const Step& st) { return st.name == s; }))
        throw InputError(fmt::format("--skip: unknown step '{}'", s));
    }
    const fs::path staging = io::make_staging_folder(root);
    const std::vector<Step> steps = run_steps(staging, form, skipped("bench"));
    fs::create_directories(staging / "logs");
    std::string index = fmt::format(
        "# sglab results\n\nProduced by `{}`; every section names the command that "
        "made it and the form it ran in.\n\n",
        display_command(run_arguments(root, form, *skip)));
    Seen seen;
    int failures = 0;
    const std::size_t to_run = static_cast<std::size_t>(std::count_if(
        steps.begin(), steps.end(), [&](const Step& st) { return !skipped(st.name); }));
    std::size_t ran = 0;
    // The terminal, kept while each step's output goes to its log.
    const int tty = io::stderr_is_terminal() ? ::dup(STDERR_FILENO) : -1;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const Step& step = steps[i];
      if (skipped(step.name)) continue;
      if (step.name == "pareto" && !has_gpu_costs(step)) {
        ++ran;
        const std::string why =
            "skipped: the cost table has no GPU costs (no RADV null device for gpucost, or its "
            "step skipped); pareto-cpu has the CPU cost";
        fmt::print("{:<10} {}\n", step.name, why);
        index += fmt::format("## {}\n\n`{}` — {}\n\n", step.name,
                             display_command(shown[i].arguments), why);
        continue;
      }
      ++ran;
      const auto start = std::chrono::steady_clock::now();
      int status = 1;
      {
        StepTicker ticker(tty, fmt::format("sglab run [{}/{}] {} ({})", ran, to_run, step.name,
                                           form_name(step.form)));
        status = run_logged(step, staging / "logs" / (step.name + ".log"));
      }
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fmt::print("{:<10} {:>7.1f} s  {}\n", step.name, secs,
                 status == 0 ? "ok"
                             : fmt::format("FAILED, see {}",
                                           (root / "logs" / (step.name + ".log")).string()));
      std::fflush(stdout);
      if (status != 0) ++failures;
      index += section(staging, shown[i], status, secs, seen);
    }
    if (tty >= 0) ::close(tty);
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    index += fmt::format("Total: {:.1f} s.\n", total);
    io::write_file_atomic(staging / "index.md", index);
    io::write_output_manifest(staging, display_command(run_arguments(root, form, *skip)));
    const std::string kept = io::replace_folder(staging, root, "--out");
    fmt::print("total {:.1f} s; wrote {}\n", total, (root / "index.md").string());
    if (!kept.empty()) fmt::print(stderr, "sglab run: {}", kept);
    if (failures) throw std::runtime_error(fmt::format("{} step(s) failed", failures));
  });
}

}  // namespace sglab::app
