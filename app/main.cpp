// sglab — spherical Gaussian diffuse lighting: fit, validate, compare.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <sglab/version.hpp>

#include "app/commands.hpp"
#include "fit/solver_log.hpp"

namespace {

// The exit codes of every subcommand (docs/cli.md, "Exit codes").
constexpr const char* kExitCodes =
    "Exit codes: 0 success; 1 failure (a fit did not converge, a file could not be written, an "
    "internal error); 2 bad input (an unknown subcommand or option, a malformed value or file; the "
    "message names it). Command-line errors that CLI11 finds (its own codes are 100-127) exit with "
    "2 as well.";

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// "unknown subcommand 'x'" (with the nearest name) when the first argument
// is not an option and names no subcommand.
std::optional<std::string> unknown_subcommand(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return std::nullopt;
  const std::string_view word = argv[1];
  std::string names, nearest;
  std::size_t best = 3;  // suggest only within two edits
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    if (sub->get_name() == word) return std::nullopt;
    names += (names.empty() ? "" : ", ") + sub->get_name();
    if (const std::size_t d = edit_distance(word, sub->get_name()); d < best)
      best = d, nearest = sub->get_name();
  }
  std::string quoted;
  for (unsigned char c : word.substr(0, 64))
    quoted +=
        c >= 0x20 && c < 0x7f ? std::string(1, static_cast<char>(c)) : fmt::format("\\x{:02x}", c);
  return fmt::format("unknown subcommand '{}'{}; the subcommands are: {} (sglab --help)", quoted,
                     nearest.empty() ? "" : fmt::format(" (did you mean '{}'?)", nearest), names);
}

}  // namespace

int main(int argc, char** argv) {
  // glog once, before any solver runs
  sglab::fit::init_solver_logging(argc > 0 ? argv[0] : "sglab");
  CLI::App app{"sglab: refit, validate and compare spherical Gaussian diffuse lighting methods"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("sglab ") + SGLAB_VERSION,
                       "print the version and exit");
  app.footer(kExitCodes);
  sglab::app::add_methods_command(app);
  sglab::app::add_table_command(app);
  sglab::app::add_constants_command(app);
  sglab::app::add_fit_command(app);
  sglab::app::add_run_command(app);
  sglab::app::add_erf_command(app);
  sglab::app::add_sweep_command(app);
  sglab::app::add_stability_command(app);
  sglab::app::add_range_command(app);
  sglab::app::add_reference_command(app);
  sglab::app::add_figures_command(app);
  sglab::app::add_claims_command(app);
  sglab::app::add_bench_command(app);
  sglab::app::add_pareto_command(app);
  sglab::app::add_recommend_command(app);
  sglab::app::add_export_command(app);
  sglab::app::add_eval_command(app);
  sglab::app::add_gpucost_command(app);
  sglab::app::add_envmap_command(app);
  if (const auto typo = unknown_subcommand(app, argc, argv)) {
    fmt::print(stderr, "sglab: error: {}\n", *typo);
    return 2;
  }
  return sglab::app::run_and_map_exit_code(app, [&] { app.parse(argc, argv); });
}
