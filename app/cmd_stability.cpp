// `sglab stability`: every runtime function and method over special inputs
// (κ = 0, denormals, huge, +inf, NaN; c at and just outside ±1; non-unit and
// opposite axes), float and double: counts of NaN / Inf / negative /
// out-of-range outputs for valid and for invalid inputs, and where they occur.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "export/vulkan_runner.hpp"
#include "validate/stability.hpp"
#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {

// `--half`: every exportable method's float and half GLSL exports on the first
// Vulkan device over κ = 1e-5 … 1e5 (8 per decade, the top beyond the largest
// half, 65504) × 41 cosines, and where half fails (validate::half_ranges_table).
// Throws vulkan::Unavailable without a device or without shaderFloat16.
validate::Table half_ranges() {
  shader::vulkan::Device device;  // first: no reference work without a device
  validate::SweepGrid grid;
  grid.kappa_lo = 1e-5;
  grid.kappa_hi = 1e5;
  grid.kappa_count = 81;
  validate::SweepOptions options;
  options.precisions.clear();
  options.progress = io::stderr_is_terminal();
  std::vector<validate::SweepMethod> methods;
  for (const auto& m : validate::registered_sweep_methods())
    if (m.quantity == validate::Quantity::irradiance) methods.push_back(m);
  validate::SweepResult r = validate::sweep(grid, methods, options);
  for (auto precision : {shader::Precision::float32, shader::Precision::float16})
    shader::vulkan::add_device_entries(r, methods, shader::Language::glsl, device, true, precision);
  return validate::half_ranges_table(r);
}

struct StabilityArgs {
  std::string out = "out/stability";
  bool json = false;
  bool half = false;
};

// stability.json: the probed inputs, the full table, sglab's own failures on
// valid inputs and the half ranges (with --half).
std::string stability_json(const validate::StabilityReport& report, const validate::Table& full,
                           const std::optional<validate::Table>& half) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::object();
  // JSON has no NaN / inf: spell the non-finite inputs as strings.
  const auto list = [](const std::vector<double>& xs) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (double x : xs) {
      if (std::isfinite(x))
        a.push_back(x);
      else
        a.push_back(std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf"));
    }
    return a;
  };
  doc["inputs"] = {{"kappa_float", list(report.kappas_float)},
                   {"kappa_double", list(report.kappas_double)},
                   {"cosine_float", list(report.cosines_float)},
                   {"cosine_double", list(report.cosines_double)}};
  doc["results"] = validate::to_json_records(full);
  nlohmann::ordered_json own = nlohmann::ordered_json::array();
  for (const validate::StabilityRow* r : validate::own_failures_on_valid_inputs(report))
    own.push_back(fmt::format("{} ({})", r->function, io::to_string(r->precision)));
  doc["sglab_failures_on_valid_inputs"] = std::move(own);
  if (half) doc["half"] = validate::to_json_records(*half);
  return doc.dump(2) + "\n";
}

// The findings (and half ranges) on stdout, and whether sglab's own code fails on valid inputs.
void print_stability_summary(const validate::StabilityReport& report,
                             const validate::Table& findings,
                             const std::optional<validate::Table>& half,
                             const std::filesystem::path& dir) {
  fmt::print("{}\n", validate::to_markdown(findings));
  if (half) fmt::print("{}\n", validate::to_markdown(*half));
  const auto own_failures = validate::own_failures_on_valid_inputs(report);
  if (own_failures.empty())
    fmt::print(
        "sglab's own primitives and methods (origin sglab or refit): no NaN / Inf / negative / "
        "out-of-range output on valid inputs.\n");
  else
    for (const validate::StabilityRow* r : own_failures)
      fmt::print(
          "WARNING: {} ({}, origin {}) fails on valid inputs, e.g. {}\n", r->function,
          io::to_string(r->precision), to_string(r->origin), [&] {
            for (std::size_t k = 0; k < validate::kFailureKinds; ++k)
              if (r->failures[k].count && r->is_failure(static_cast<validate::FailureKind>(k)))
                return r->failures[k].example;
            return std::string();
          }());
  fmt::print("Written to {}: stability.{{csv,md,json}}, findings.{{csv,md}}{}\n", dir.string(),
             half ? ", stability_half.{csv,md}" : "");
}

// `sglab stability`: the tables into --out (when files are written) and the
// summary on stdout (the JSON with --json; files only where asked, `out_given`).
void run_stability(const StabilityArgs& args, bool out_given) {
  const validate::StabilityReport report = validate::stability();
  std::optional<validate::Table> half;
  if (args.half) half = half_ranges();
  const validate::Table full = validate::stability_table(report);
  const validate::Table findings = validate::stability_findings_table(report);
  const std::filesystem::path dir(args.out);
  const bool write_files = !args.json || out_given;
  using validate::TableFormat;
  if (write_files) {
    validate::write_table(full, dir, "stability", {TableFormat::csv, TableFormat::markdown});
    validate::write_table(findings, dir, "findings", {TableFormat::csv, TableFormat::markdown});
    if (half)
      validate::write_table(*half, dir, "stability_half",
                            {TableFormat::csv, TableFormat::markdown});
  }
  const std::string json = stability_json(report, full, half);
  if (write_files) io::write_file_atomic(dir / "stability.json", json);
  if (args.json)
    fmt::print("{}", json);
  else
    print_stability_summary(report, findings, half, dir);
}

}  // namespace

void add_stability_command(CLI::App& app) {
  auto args = std::make_shared<StabilityArgs>();
  auto* cmd = app.add_subcommand("stability",
                                 "NaN / Inf / negative / out-of-range outputs of every function "
                                 "and method over special inputs");
  auto* out_option =
      add_path_option(cmd, "--out", args->out, "output directory (with --json: only when given)")
          ->capture_default_str();
  cmd->add_flag("--json", args->json,
                "print the full table as JSON on stdout; writes no file unless --out is given");
  cmd->add_flag("--half", args->half,
                "also run every method's half export (`sglab export --precision half`) on the "
                "first Vulkan device and report the κ range where half survives "
                "(stability_half.{csv,md}); exit 1 without a device with shaderFloat16");
  cmd->callback([args, out_option] { run_stability(*args, out_option->count() > 0); });
}

}  // namespace sglab::app
