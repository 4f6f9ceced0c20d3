// `sglab range`: every irradiance method against the reference engine over all the κ a float
// holds (validate/kappa_range.hpp), checked against the κ range and bound on its registry card
// (sglab::ValidRange): kappa_range.{csv,md} into --out, the table on stdout (JSON with --json).
// Exit 1 when a card's bound fails somewhere on its stated range.
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "validate/kappa_range.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {

struct RangeArgs {
  std::string out = "out/range";
  int per_decade = 16;
  int cosines = 401;
  int layer = 129;
  bool no_refine = false;
  bool json = false;
};

void run_range(const RangeArgs& args) {
  const std::filesystem::path dir(args.out);
  const std::vector<std::filesystem::path> outputs = {dir / "kappa_range.csv",
                                                      dir / "kappa_range.md"};
  io::check_output_folder(dir);  // before the scan: a bad --out costs nothing
  for (const auto& p : outputs) io::check_output_path(p);

  validate::KappaScanOptions o;
  o.per_decade = args.per_decade;
  o.cosines = args.cosines;
  o.layer = args.layer;
  o.refine = !args.no_refine;
  o.progress = io::stderr_is_terminal();
  // Each card's ends and the float next beyond them, so the table judges the very ends.
  for (const Method& m : irradiance_methods)
    for (float k : {m.valid.kappa_lo, m.valid.kappa_hi})
      o.extra_kappas.insert(o.extra_kappas.end(), {double(k), double(std::nextafter(k, 0.0f)),
                                                   double(std::nextafter(k, kFloatMax))});
  const validate::KappaScan scan = validate::scan_kappa_range(irradiance_methods, o);
  const validate::Table table = validate::kappa_range_table(scan, irradiance_methods, o);

  io::write_files_atomic(
      {{outputs[0], validate::to_csv(table)}, {outputs[1], validate::to_markdown(table) + "\n"}});
  if (args.json)
    fmt::print("{}\n", validate::to_json(table).dump(2));
  else
    fmt::print("{}\nWritten to {}: kappa_range.{{csv,md}}\n", validate::to_markdown(table),
               dir.string());
  std::vector<std::string> failed;
  const std::size_t holds = table.column_index("holds");
  for (const auto& row : table.rows())
    if (std::get<std::string>(row[holds]) != "yes") failed.push_back(std::get<std::string>(row[0]));
  if (!failed.empty())
    throw std::runtime_error(fmt::format(
        "the stated bound fails on the stated κ range of: {} (include/sglab/registry.hpp)",
        fmt::format("{}", fmt::join(failed, ", "))));
}

}  // namespace

void add_range_command(CLI::App& app) {
  auto args = std::make_shared<RangeArgs>();
  auto* cmd = app.add_subcommand(
      "range",
      "Every irradiance method's worst peak_rel at each κ from 0 to FLT_MAX, against the κ "
      "range and bound on its registry card");
  cmd->footer(
      "peak_rel = |Ê − E| / E(1, κ), the irradiance error relative to the lobe's peak "
      "(docs/quantities.md). Exit 1 when a card's bound fails on its stated range.");
  add_path_option(cmd, "--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--per-decade", args->per_decade, "κ per decade")
      ->check(count_in(1, 1000))
      ->capture_default_str();
  cmd->add_option("--cosines", args->cosines, "uniform cosines over [-1, 1]")
      ->check(count_in(2, 100001))
      ->capture_default_str();
  cmd->add_option("--layer", args->layer,
                  "cosines t/sqrt(kappa), t evenly spaced over [-8, 8], where a sharp light's "
                  "irradiance turns on")
      ->check(count_in(0, 100001))
      ->capture_default_str();
  cmd->add_flag("--no-refine", args->no_refine,
                "skip the Brent search for the worst cosine between grid cosines");
  cmd->add_flag("--json", args->json, "print the table as JSON on stdout");
  cmd->callback([args] { run_range(*args); });
}

}  // namespace sglab::app
