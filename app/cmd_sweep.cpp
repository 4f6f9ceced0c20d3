// `sglab sweep`: every method against the reference over the standard grid of docs/quantities.md
// (or a custom one), in float and double, with the metrics of docs/quantities.md. Writes the
// summary, per-κ and per-point tables into --out and prints the summary.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "common/args.hpp"
#include "common/io.hpp"
#include "export/vulkan_runner.hpp"
#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {

// --kappa LO:HI:N (common/args.hpp; float: the sweep rounds its inputs to float)
void parse_kappa_option(const std::string& text, validate::SweepGrid& grid) {
  io::KappaRangeRules rules;
  rules.with_count = true;
  // N is bounded by the grid's size limit (SweepGrid::validate, which says the
  // memory a refused grid would need), not by the parser's default cap.
  rules.max_count = std::numeric_limits<int>::max();
  const auto parsed = io::parse_kappa_range(text, rules);
  if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--kappa: " + *why);
  const auto& r = std::get<io::KappaRange>(parsed);
  grid.kappa_lo = r.lo;
  grid.kappa_hi = r.hi;
  grid.kappa_count = r.count;
}

// --cosines N: at least 2 (the grid includes c = -1 and c = 1); the grid limit
// (SweepGrid::validate) bounds it.
void parse_cosines_option(const std::string& text, validate::SweepGrid& grid) {
  const auto n = io::parse_count(text, 2, std::numeric_limits<int>::max());
  if (const auto* why = std::get_if<std::string>(&n)) throw InputError("--cosines: " + *why);
  grid.cosine_count = static_cast<int>(std::get<long long>(n));
}

std::vector<validate::SweepMethod> select_methods(const std::vector<std::string>& ids) {
  auto all = validate::registered_sweep_methods();
  if (ids.empty()) return all;
  std::vector<std::string> known;
  for (const auto& m : all)
    if (std::find(known.begin(), known.end(), m.method.id) == known.end())
      known.emplace_back(m.method.id);
  for (const std::string& id : ids)
    if (std::find(known.begin(), known.end(), id) == known.end())
      throw InputError(fmt::format("--method: unknown method id '{}'; known ids: {}", id,
                                   fmt::join(known, ", ")));
  std::vector<validate::SweepMethod> out;
  for (const auto& m : all)
    if (std::find(ids.begin(), ids.end(), m.method.id) != ids.end()) out.push_back(m);
  return out;
}

// max over the grid of |x_device − x_float|/x(1, κ) for every device entry
// that has a C++ float entry of the same method and quantity.
validate::Table device_vs_float_table(const validate::SweepResult& r) {
  validate::Table t(
      "Vulkan device against the C++ runtime in float: max |x_device - x_float|/x(1, κ) over the "
      "grid",
      {{"method"},
       {"quantity"},
       {"precision"},
       {"max_diff_peak_rel", 3},
       {"worst_kappa", 4},
       {"worst_cosine", 4}});
  for (const auto& e : r.entries) {
    if (e.precision.backend != io::Backend::vulkan) continue;
    const auto* f = r.find(e.method, e.quantity, io::kCpuFloat);
    if (!f || f->values.size() != e.values.size()) continue;
    double worst = 0, wk = NAN, wc = NAN;
    for (std::size_t k = 0; k < r.kappas.size(); ++k)
      for (std::size_t j = 0; j < r.cosines.size(); ++j) {
        const std::size_t i = r.index(k, j);
        const double d = std::fabs(e.values[i] - f->values[i]) / r.peak_value(e.quantity, k);
        if (!(d <= worst)) {
          worst = std::isnan(d) ? INFINITY : d;
          wk = r.kappas[k];
          wc = r.cosines[j];
        }
      }
    t.add_row({validate::Table::text(e.method), validate::Table::text(to_string(e.quantity)),
               validate::Table::text(to_string(e.precision)), validate::Table::real(worst),
               validate::Table::real(wk), validate::Table::real(wc)});
  }
  return t;
}

struct SweepArgs {
  std::string kappa;
  std::string cosines;
  std::string out = "out/sweep";
  bool json = false;
  std::vector<std::string> methods;
  std::vector<std::string> backends;    // cpu, vulkan
  std::string lang = "both";            // shader language(s) of the vulkan backend
  std::vector<std::string> precisions;  // float, half: the exports the vulkan backend runs
};

// --precision float,half: the precisions of the exports the vulkan backend runs (default float).
std::vector<shader::Precision> checked_precisions(const std::vector<std::string>& asked) {
  std::vector<shader::Precision> out;
  for (const std::string& p : asked) {
    const auto parsed =
        io::parse_option("--precision", p, {io::Precision::float32, io::Precision::float16});
    if (std::find(out.begin(), out.end(), parsed) == out.end()) out.push_back(parsed);
  }
  if (out.empty()) out.push_back(shader::Precision::float32);
  return out;
}

// The device rows of every language and precision; half rows are skipped,
// with the reason on stderr, on a device without shaderFloat16. With float:
// also the per-light split exports (`sglab export --split`, rows vulkan_split /
// vulkan_hlsl_split), lights filled on the host by the C++ runtime; the split
// export is float only, so half runs add no split rows.
std::vector<std::string> add_all_device_entries(validate::SweepResult& result,
                                                const std::vector<validate::SweepMethod>& methods,
                                                const std::vector<shader::Language>& langs,
                                                const std::vector<shader::Precision>& precisions,
                                                shader::vulkan::Device& device) {
  std::vector<std::string> skipped;
  for (auto precision : precisions) {
    if (precision == shader::Precision::float16 && !device.has_float16()) {
      fmt::print(
          stderr,
          "sglab sweep: no half rows: {} offers no half arithmetic in shaders (shaderFloat16)\n",
          device.name());
      continue;
    }
    for (auto lang : langs)
      skipped = shader::vulkan::add_device_entries(result, methods, lang, device, true, precision);
    if (precision == shader::Precision::float32)
      for (auto lang : langs)
        shader::vulkan::add_split_device_entries(result, methods, lang, device);
  }
  return skipped;
}

// The backends of --backend: cpu (the default), vulkan, or auto (cpu, plus
// vulkan when a device can be created).
struct Backends {
  bool cpu = true, vulkan = false, vulkan_if_available = false;
};
Backends parse_backends(const std::vector<std::string>& asked) {
  Backends b;
  b.cpu = asked.empty();
  for (const std::string& x : asked) {
    if (x == "auto") {
      b.cpu = b.vulkan_if_available = true;
      continue;
    }
    const auto backend = io::parse_enum<io::Backend>(x);
    if (!backend)
      throw InputError(
          fmt::format("--backend: expected cpu, vulkan or auto, got {}", io::quote_escaped(x)));
    (*backend == io::Backend::cpu ? b.cpu : b.vulkan) = true;
  }
  return b;
}

// The first Vulkan device: required with vulkan (throws vulkan::Unavailable
// with the reason), optional with auto (then `vulkan` says whether there is one).
std::unique_ptr<shader::vulkan::Device> open_device(Backends& b) {
  if (b.vulkan) return std::make_unique<shader::vulkan::Device>();
  if (!b.vulkan_if_available) return nullptr;
  try {
    auto device = std::make_unique<shader::vulkan::Device>();
    b.vulkan = true;
    return device;
  } catch (const shader::vulkan::Unavailable& e) {
    fmt::print(stderr, "sglab sweep: --backend auto: no Vulkan rows: {}\n", e.what());
  }
  return nullptr;
}

// The device rows, in method-major order as the CPU entries.
void add_vulkan_rows(validate::SweepResult& result,
                     const std::vector<validate::SweepMethod>& methods,
                     const std::vector<shader::Language>& langs,
                     const std::vector<shader::Precision>& precisions,
                     shader::vulkan::Device& device, bool json) {
  const std::vector<std::string> skipped =
      add_all_device_entries(result, methods, langs, precisions, device);
  if (!skipped.empty() && !json)
    fmt::print(stderr, "sglab sweep: vulkan backend: not exportable, skipped: {}\n",
               fmt::join(skipped, ", "));
  std::stable_sort(result.entries.begin(), result.entries.end(), [&](const auto& a, const auto& b) {
    auto rank = [&](const validate::SweepEntry& e) {
      for (std::size_t i = 0; i < methods.size(); ++i)
        if (methods[i].method.id == e.method && methods[i].quantity == e.quantity) return i;
      return methods.size();
    };
    return rank(a) < rank(b);
  });
}

// The tables into --out (when files are written), summary.json, and the
// summary on stdout (as JSON with --json).
void write_sweep_report(const SweepArgs& args, bool write_files, const validate::SweepGrid& grid,
                        const validate::SweepResult& result, const Backends& b,
                        const std::string& device_name) {
  const validate::Table summary = validate::summary_table(result);
  const std::filesystem::path dir(args.out);
  using validate::TableFormat;
  if (write_files) {
    validate::write_table(summary, dir, "summary", {TableFormat::csv, TableFormat::markdown});
    validate::write_table(validate::per_kappa_table(result), dir, "per_kappa",
                          {TableFormat::csv, TableFormat::markdown});
    validate::write_table(validate::points_table(result), dir, "points", {TableFormat::csv});
  }

  // The device against the C++ runtime in float, point by point.
  std::optional<validate::Table> device_vs_float;
  if (b.vulkan && b.cpu) device_vs_float = device_vs_float_table(result);
  if (device_vs_float && write_files)
    validate::write_table(*device_vs_float, dir, "device_vs_float",
                          {TableFormat::csv, TableFormat::markdown});

  nlohmann::ordered_json doc = nlohmann::ordered_json::object();
  doc["grid"] = {{"kappa_lo", grid.kappa_lo},
                 {"kappa_hi", grid.kappa_hi},
                 {"kappa_count", grid.kappa_count},
                 {"cosine_count", grid.cosine_count}};
  if (b.vulkan) {
    doc["backend"] = b.cpu ? "cpu,vulkan" : "vulkan";
    doc["device"] = device_name;
  }
  doc["results"] = validate::to_json_records(summary);
  if (device_vs_float) doc["device_vs_float"] = validate::to_json_records(*device_vs_float);
  const std::string json = doc.dump(2) + "\n";
  if (write_files) io::write_file_atomic(dir / "summary.json", json);

  if (args.json)
    fmt::print("{}", json);
  else
    fmt::print("{}\n{}Written to {}: summary.{{csv,md,json}}, per_kappa.{{csv,md}}, points.csv{}\n",
               validate::to_markdown(summary),
               device_vs_float ? validate::to_markdown(*device_vs_float) + "\n" : "", dir.string(),
               device_vs_float ? ", device_vs_float.{csv,md}" : "");
}

// `sglab sweep`: the options checked, the CPU sweep, the device rows, the report.
// --json prints to stdout; files are written only where asked (`out_given`).
void run_sweep(const SweepArgs& args, bool out_given) {
  validate::SweepGrid grid;  // the standard grid (docs/quantities.md)
  if (!args.kappa.empty()) parse_kappa_option(args.kappa, grid);
  if (!args.cosines.empty()) parse_cosines_option(args.cosines, grid);
  try {
    grid.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  const auto methods = select_methods(args.methods);
  Backends b = parse_backends(args.backends);
  const std::vector<shader::Language> langs = checked_languages(args.lang);
  const auto precisions = checked_precisions(args.precisions);
  if (!args.precisions.empty() && !b.vulkan && !b.vulkan_if_available)
    throw InputError(
        "--precision: chooses the exports of the vulkan backend; add --backend vulkan (or auto)");

  validate::SweepOptions options;
  if (!b.cpu) options.precisions.clear();
  options.progress = io::stderr_is_terminal();
  validate::SweepResult result = validate::sweep(grid, methods, options);
  std::string device_name;
  const std::unique_ptr<shader::vulkan::Device> device = open_device(b);
  if (b.vulkan) {
    device_name = device->name();
    add_vulkan_rows(result, methods, langs, precisions, *device, args.json);
  }
  write_sweep_report(args, !args.json || out_given, grid, result, b, device_name);
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand(
      "sweep",
      "Accuracy of every method against the reference over a (κ, c) grid, in float and double");
  cmd->footer(
      "peak_rel = |x̂ − x| / x(1, κ) for x = E, H or s: the error relative to the lobe's peak "
      "(docs/quantities.md)");
  cmd->add_option("--kappa", args->kappa,
                  "κ grid LO:HI:N, N values log-spaced over [LO, HI] (default: the standard grid, "
                  "1e-3:1e4:29)");
  cmd->add_option(
      "--cosines", args->cosines,
      fmt::format(
          "number of cosines evenly spaced over [-1, 1] (default 41); κ count × cosines is at most "
          "{} points",
          validate::SweepGrid::kMaxPoints));
  auto* out_option =
      add_path_option(cmd, "--out", args->out, "output directory (with --json: only when given)")
          ->capture_default_str();
  cmd->add_flag("--json", args->json,
                "print the summary as JSON on stdout; writes no file unless --out is given");
  cmd->add_option("--method", args->methods, "restrict to this method id (repeatable)");
  cmd->add_option("--backend", args->backends,
                  "cpu (the C++ runtime in float and double, default) and/or vulkan (each "
                  "irradiance method's `sglab export` run as a compute shader on the first Vulkan "
                  "device); auto = cpu, plus vulkan when a device can be created; comma-separated "
                  "or repeated")
      ->delimiter(',');
  cmd->add_option("--lang", args->lang,
                  "shader language(s) of the vulkan backend: glsl, hlsl or both")
      ->capture_default_str();
  cmd->add_option(
         "--precision", args->precisions,
         "precision(s) of the exports the vulkan backend runs: float (default) and/or half (`sglab "
         "export --precision half`, rows vulkan_half and vulkan_hlsl_half); comma-separated")
      ->delimiter(',');
  cmd->callback([args, out_option] { run_sweep(*args, out_option->count() > 0); });
}

}  // namespace sglab::app
