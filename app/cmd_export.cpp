// `sglab export`: one irradiance method as self-contained GLSL, HLSL or C++
// source with its constants baked in (compiled-in, or from a constants JSON),
// its own erf/erfc/expm1 approximations, and a header comment carrying the
// source paper, the constants' provenance, the error budget, the GPU cost
// (GLSL and HLSL, from the cost table) and the command. With --probe: a
// fitted probe as probe_irradiance(n) (export/probe_export.hpp).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "cost/cost_table.hpp"
#include "export/gpu_cost.hpp"
#include "export/shader_export.hpp"
#include "fit/constants_io.hpp"
#include "probe/probe_source.hpp"

namespace sglab::app {

namespace {

// Objective, fit command, date and source of a constant set, on one line.
std::string provenance_line(const fit::ordered_json& j) {
  const auto& p = j["provenance"];
  std::string prov;
  const auto add = [&](const std::string& s) { prov += (prov.empty() ? "" : "; ") + s; };
  if (p.contains("objective") && p["objective"].is_string())
    add("objective: " + p["objective"].get<std::string>());
  if (p.contains("command") && p["command"].is_string())
    add("fitted by `" + p["command"].get<std::string>() + "`");
  if (p.contains("date") && p["date"].is_string()) add(p["date"].get<std::string>());
  if (p.contains("source") && p["source"].is_string())
    add("source: " + p["source"].get<std::string>());
  return prov;
}

// A constant-set JSON (data/constants/*.json, or one `sglab fit … --out DIR`
// wrote), read by the same strict loader as `sglab constants` and fit (size and
// depth limits, duplicate keys refused, schema-validated).
shader::ConstantSet read_constant_set(const std::string& path) {
  fit::ordered_json j;
  try {
    j = fit::load_constant_set(path);
  } catch (const fit::ConstantsError& e) {
    throw InputError(fmt::format("--constants: {}", e.what()));
  }
  shader::ConstantSet s;
  s.cpp_type = j["cpp_type"].get<std::string>();
  s.cpp_name = j["cpp_name"].get<std::string>();
  for (const auto& [name, value] : j["coefficients"].items()) {
    std::vector<double> v;
    if (value.is_array())
      for (const auto& x : value) v.push_back(x.get<double>());
    else
      v.push_back(value.get<double>());
    s.members.emplace_back(name, std::move(v));
  }
  s.provenance = fmt::format("from {}; {}", path, provenance_line(j));
  const auto& p = j["provenance"];
  if (p.contains("achieved") && p["achieved"].is_object() &&
      p["achieved"].contains("irradiance_max_peak_rel") &&
      p["achieved"]["irradiance_max_peak_rel"].is_number())
    s.achieved_irradiance_error = p["achieved"]["irradiance_max_peak_rel"].get<double>();
  return s;
}

// The error measured on Vulkan for `method` in the committed results
// (data/results/vulkan_sweep.json, written by `sglab sweep --backend vulkan`).
void add_vulkan_error(shader::ErrorBudget& b, const std::string& method, shader::Language lang,
                      bool split, shader::Precision export_precision) {
  const auto root = fit::find_project_root(std::filesystem::current_path());
  if (!root) return;  // not inside a checkout: the header names no measured error
  const auto file = *root / "data" / "results" / "vulkan_sweep.json";
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return;
  try {
    const auto doc = nlohmann::json::parse(io::read_file(file));
    const char* suffix = split                                            ? "_split"
                         : export_precision == shader::Precision::float16 ? "_half"
                                                                          : "";
    const std::string precision =
        std::string(lang == shader::Language::hlsl ? "vulkan_hlsl" : "vulkan") + suffix;
    for (const auto& rec : doc.at("results"))
      if (rec.at("method") == method && rec.at("quantity") == "irradiance" &&
          rec.at("precision") == precision && rec.at("max_peak_rel").is_number()) {
        b.vulkan = rec["max_peak_rel"].get<double>();
        b.vulkan_device =
            fmt::format("{}, {} export{}, data/results/vulkan_sweep.json",
                        doc.value("device", std::string("?")),
                        lang == shader::Language::hlsl ? "HLSL" : "GLSL", split ? " (split)" : "");
      }
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: {}", file.string(), e.what()));
  }
}

// The families whose GPU cost an export's header states: RDNA2 and RDNA3.
constexpr const char* kHeaderFamilies[] = {"navi21", "gfx1100"};

// The GPU cost of exactly this code in the committed cost table
// (data/results/costs.json, "gpu" section, written by `sglab gpucost --out`):
// the rows of the method and language of one call per invocation (harness
// single, compile path none) whose SPIR-V hash is that of `exported` in that
// harness (comments do not reach the SPIR-V, so the header itself does not
// change it). Other code (--constants, a stale table): not measured.
void add_gpu_cost(shader::ExportRequest& req, const shader::ExportResult& exported) {
  for (const char* family : kHeaderFamilies) req.gpu_cost.push_back({family, std::nullopt});
  const auto path = cost::default_cost_table_path();
  if (!path) return;
  const auto table = cost::read_existing_cost_table(*path);
  if (!table || !table->gpu) return;
  const std::string hash = shader::gpu::spirv_hash(
      shader::gpu::export_shader(req.method, req.lang, exported, req.precision).spirv);
  for (shader::GpuCost& cost : req.gpu_cost)
    for (const cost::gpu::Row& row : table->gpu->rows)
      if (row.family == cost.family && row.method == req.method && row.lang == req.lang &&
          row.split == req.split && row.precision == shader::to_string(req.precision) &&
          row.harness == cost::gpu::Harness::single &&
          row.compile == cost::gpu::CompilePath::none && row.spirv_hash == hash)
        cost.inverse_throughput = row.stats.inverse_throughput;
  req.gpu_cost_source = fmt::format("{}, data/results/costs.json", table->gpu->driver);
}

struct ExportArgs {
  std::string lang;
  std::string method;
  std::string constants;
  bool split = false;
  std::string precision = "float";
  std::string probe;
};

// `sglab export --probe FILE --lang L`: the probe's probe_irradiance(n).
void export_probe(const ExportArgs& args, io::Language lang) {
  if (!args.method.empty() || !args.constants.empty() || args.split || args.precision != "float")
    throw InputError(
        "--probe: exports a fitted probe with the method it names; --method, --constants, --split "
        "and --precision do not apply");
  const envmap::Probe probe = probe::read_probe_file(args.probe);
  const std::string command =
      fmt::format("sglab export --probe {} --lang {}", args.probe, io::to_string(lang));
  try {
    fmt::print("{}", shader::export_probe(lang, probe::probe_terms(probe, command)).source);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: {}", args.probe, e.what()));
  }
}

// --split: the per-light form of req's method (refused for a method without
// one, and with --precision half: the split export is float only).
void set_split(shader::ExportRequest& req) {
  const auto split = shader::split_methods();
  if (std::find(split.begin(), split.end(), req.method) == split.end())
    throw InputError(
        fmt::format("--split: method '{}' has no per-light split; methods with one: {}", req.method,
                    fmt::join(split, ", ")));
  if (req.precision == shader::Precision::float16)
    throw InputError(
        "--split with --precision half: the per-light split export is float only (its light struct "
        "is std430 floats filled by the float runtime); use one or the other");
  req.split = true;
  req.command += " --split";
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand("export",
                                 "One irradiance method (or a fitted probe) as self-contained GLSL "
                                 "4.50, HLSL (SM6) or C++ source, constants baked in");
  cmd->add_option("--lang", args->lang, "glsl, hlsl or cpp")->required();
  cmd->add_option("--method", args->method,
                  "irradiance method id (see `sglab methods`); this or --probe");
  add_path_option(cmd, "--probe", args->probe,
                  "a fitted probe (JSON object as `sglab envmap recommend --write-probe` writes): "
                  "exports probe_irradiance(n), its lobes with the method it names");
  add_path_option(cmd, "--constants", args->constants,
                  "constant-set JSON replacing the compiled-in set of the same type (e.g. one "
                  "`sglab fit ... --out DIR` wrote)");
  cmd->add_flag("--split", args->split,
                "per-light form: a light struct (std430), sglab_light_<ID>(float kappa) that fills "
                "it once per light, and sglab_irradiance_<ID>(light, float cosine) per pixel");
  cmd->add_option(
         "--precision", args->precision,
         "float, or half (16-bit floats: GLSL float16_t, HLSL half with 16-bit types; not for cpp)")
      ->capture_default_str();
  cmd->callback([args] {
    const auto lang = io::parse_option<io::Language>("--lang", args->lang);
    if (!args->probe.empty()) return export_probe(*args, lang);
    if (args->method.empty()) throw InputError("--method or --probe is required");
    const auto precision = io::parse_option("--precision", args->precision,
                                            {io::Precision::float32, io::Precision::float16});
    if (precision == io::Precision::float16 && lang == io::Language::cpp)
      throw InputError(
          "--precision half: the C++ export is float only (g++'s _Float16 may keep float "
          "intermediates, so it would not be a faithful half twin); use --lang glsl or hlsl");
    const auto known = shader::exportable_methods();
    if (std::find(known.begin(), known.end(), args->method) == known.end())
      throw InputError(
          fmt::format("--method: unknown or non-exportable method '{}'; exportable: {}",
                      args->method, fmt::join(known, ", ")));
    shader::ExportRequest req = shader::standard_request(lang, args->method, precision);
    if (args->split) set_split(req);
    // Provenance of the compiled-in sets from the JSON they were generated
    // from, when the source tree is at hand.
    try {
      for (const auto& set : fit::load_constant_sets(fit::default_constants_dir()))
        req.provenance[set["cpp_name"].get<std::string>()] =
            fmt::format("data/constants/{}-{}.json: {}", set["target"].get<std::string>(),
                        set["variant"].get<std::string>(), provenance_line(set));
    } catch (const std::runtime_error&) {
      // No source tree: the header names the compiled-in set only.
    }
    if (!args->constants.empty()) {
      req.command += " --constants " + args->constants;
      req.overrides.push_back(read_constant_set(args->constants));
      // The registry's numbers belong to the compiled-in constants: with
      // other constants, only the fit's own record (if any) is known.
      req.budget = {};
      req.budget.model = req.overrides.back().achieved_irradiance_error;
    } else {
      add_vulkan_error(req.budget, args->method, lang, req.split, precision);
    }
    shader::ExportResult result;
    try {
      result = shader::export_source(req);
      if (req.lang != shader::Language::cpp) {
        add_gpu_cost(req, result);
        result = shader::export_source(req);
      }
    } catch (const std::invalid_argument& e) {
      // The method was checked above: what remains is about the --constants set.
      throw InputError(args->constants.empty()
                           ? std::string(e.what())
                           : fmt::format("--constants: {}: {}", args->constants, e.what()));
    }
    fmt::print("{}", result.source);
  });
}

}  // namespace sglab::app
