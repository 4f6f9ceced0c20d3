// `sglab claims`: every quantitative claim of the cited sources (docs/references.md) checked
// numerically (validate/claims). Writes claims.{md,json,csv} into --out and
// prints the table as Markdown (or JSON with --json).
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "fit/targets.hpp"
#include "validate/claims.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {
struct ClaimsArgs {
  std::string out = "out/claims";
  bool json = false;
};
}  // namespace

void add_claims_command(CLI::App& app) {
  auto args = std::make_shared<ClaimsArgs>();
  auto* cmd = app.add_subcommand(
      "claims",
      "Check every quantitative claim of the cited sources (docs/references.md) numerically");
  auto* out_option =
      add_path_option(cmd, "--out", args->out, "output directory (with --json: only when given)")
          ->capture_default_str();
  cmd->add_flag("--json", args->json,
                "print the table as JSON on stdout (Markdown otherwise); writes no file unless "
                "--out is given");
  cmd->callback([args, out_option] {
    const auto claims = validate::check_claims([](const std::vector<double>& kappas) {
      return fit::optimal_steepness("steepness2022", kappas);
    });
    const validate::Table table = validate::claims_table(claims);
    const std::filesystem::path dir(args->out);
    using validate::TableFormat;
    if (!args->json || out_option->count() > 0)  // files only where asked
      validate::write_table(table, dir, "claims",
                            {TableFormat::markdown, TableFormat::json, TableFormat::csv});
    int holds = 0, part = 0, fails = 0;
    for (const auto& c : claims)
      (c.verdict == "holds" ? holds : c.verdict == "holds in part" ? part : fails)++;
    if (args->json) {
      fmt::print("{}\n", validate::to_json(table).dump(2));
    } else {
      fmt::print(
          "{}\n{} claims: {} hold, {} hold in part, {} do not hold or were not checked.\n"
          "Written to {}: claims.{{md,json,csv}}\n",
          validate::to_markdown(table), claims.size(), holds, part, fails, dir.string());
    }
  });
}

}  // namespace sglab::app
