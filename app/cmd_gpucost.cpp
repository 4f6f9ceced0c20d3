// `sglab gpucost`: what each exported method costs on AMD GPUs, from the
// statistics of AMD's shader compiler (ACO) on Mesa's RADV null devices
// (export/gpu_cost.hpp; the rows are cost/gpu_report.hpp's). Deterministic: the same driver gives
// the same numbers on every run and machine.
#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/commands.hpp"
#include "common/args.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "cost/cost_source.hpp"
#include "cost/cost_table.hpp"
#include "export/gpu_cost.hpp"

namespace sglab::app {

namespace {

namespace fs = std::filesystem;
namespace gpu = shader::gpu;

struct GpucostArgs {
  std::vector<std::string> families;
  std::vector<std::string> methods;
  std::string lang = "glsl";
  std::string form = "both";  // unsplit, split (the per-pixel function of `export --split`) or both
  std::string precision = "float";
  std::vector<std::string> harnesses;  // single, loop, setup (default all)
  std::vector<std::string> lights;     // the loop harness's light counts (default 8)
  std::vector<std::string> compiles;   // none, legalized, optimized (default none)
  bool json = false;
  bool disasm = false;
  bool skip_unavailable = false;
  std::string out;
  std::string worker_family, worker_dir;  // the per-family process (internal)
};

// The families of --families (each value a comma-separated list; default
// cost::gpu::kDefaultFamilies), in order, without repeats. An empty item or a family
// RADV does not know (cost::gpu::kKnownFamilies) is refused before any work, naming
// --families and listing the known ones.
std::vector<std::string> checked_families(const std::vector<std::string>& asked) {
  std::vector<std::string> families;
  if (asked.empty())
    for (const cost::gpu::Family& f : cost::gpu::kDefaultFamilies) families.emplace_back(f.name);
  const auto refuse = [](const std::string& why) {
    return InputError(fmt::format("--families: {}; the families RADV knows: {}", why,
                                  fmt::join(cost::gpu::kKnownFamilies, ",")));
  };
  for (const std::string& value : asked) {
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = value.find(',', start);
      const std::string f =
          value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (f.empty()) throw refuse(fmt::format("{} has an empty item", io::quote_escaped(value)));
      if (std::find(std::begin(cost::gpu::kKnownFamilies), std::end(cost::gpu::kKnownFamilies),
                    f) == std::end(cost::gpu::kKnownFamilies))
        throw refuse(fmt::format("unknown family {}", io::quote_escaped(f)));
      if (std::find(families.begin(), families.end(), f) == families.end()) families.push_back(f);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return families;
}

std::vector<shader::Precision> checked_precisions(const std::string& precision) {
  if (precision == "float") return {shader::Precision::float32};
  if (precision == "half") return {shader::Precision::float16};
  if (precision == "both") return {shader::Precision::float32, shader::Precision::float16};
  throw InputError(
      fmt::format("--precision: expected float, half or both, got '{}'", precision.substr(0, 40)));
}

std::vector<std::string> checked_methods(const std::vector<std::string>& asked) {
  const auto known = shader::exportable_methods();
  if (asked.empty()) return known;
  for (const std::string& m : asked)
    if (std::find(known.begin(), known.end(), m) == known.end())
      throw InputError(
          fmt::format("--method: unknown or non-exportable method '{}'; exportable: {}", m,
                      fmt::join(known, ", ")));
  return asked;
}

std::vector<cost::gpu::Harness> checked_harnesses(const std::vector<std::string>& asked) {
  if (asked.empty())
    return {cost::gpu::Harness::single, cost::gpu::Harness::loop, cost::gpu::Harness::setup};
  std::vector<cost::gpu::Harness> out;
  for (const std::string& h : asked) {
    const auto parsed = io::parse_option<cost::gpu::Harness>("--harness", h);
    if (std::find(out.begin(), out.end(), parsed) == out.end()) out.push_back(parsed);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<int> checked_lights(const std::vector<std::string>& asked) {
  if (asked.empty()) return {cost::gpu::kRendererLights};
  std::vector<int> out;
  for (const std::string& n : asked) {
    const auto parsed = io::parse_count(n, 1, cost::gpu::kMaxLights);
    if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--lights: " + *why);
    const int v = static_cast<int>(std::get<long long>(parsed));
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<cost::gpu::CompilePath> checked_compiles(
    const std::vector<std::string>& asked, const std::vector<shader::Language>& languages) {
  if (asked.empty()) return {cost::gpu::CompilePath::none};
  std::vector<cost::gpu::CompilePath> out;
  for (const std::string& c : asked) {
    const auto parsed = io::parse_option<cost::gpu::CompilePath>("--compile", c);
    if (std::find(out.begin(), out.end(), parsed) == out.end()) out.push_back(parsed);
  }
  std::sort(out.begin(), out.end());
  if (out == std::vector{cost::gpu::CompilePath::legalized} &&
      std::find(languages.begin(), languages.end(), shader::Language::hlsl) == languages.end())
    throw InputError(
        "--compile legalized: legalization is HLSL's (GLSL needs none); add --lang hlsl or both");
  return out;
}

// A shader of `lang` exists on compile path `c`: legalization is HLSL's.
bool applies(cost::gpu::CompilePath c, shader::Language lang) {
  return c != cost::gpu::CompilePath::legalized || lang == shader::Language::hlsl;
}

std::string command_line(const GpucostArgs& a) {
  std::string c = "sglab gpucost";
  if (!a.families.empty()) c += " --families " + fmt::format("{}", fmt::join(a.families, ","));
  for (const std::string& m : a.methods) c += " --method " + m;
  if (a.lang != "glsl") c += " --lang " + a.lang;
  if (a.form != "both") c += " --form " + a.form;
  if (a.precision != "float") c += " --precision " + a.precision;
  if (!a.harnesses.empty()) c += " --harness " + fmt::format("{}", fmt::join(a.harnesses, ","));
  if (!a.lights.empty()) c += " --lights " + fmt::format("{}", fmt::join(a.lights, ","));
  if (!a.compiles.empty()) c += " --compile " + fmt::format("{}", fmt::join(a.compiles, ","));
  if (!a.out.empty()) c += " --out " + a.out;
  return c;
}

// DIR/costs.json (DIR's cost table with this report as its "gpu" section)
// and DIR/gpu_costs.md: both are checked (each a regular file or absent, the
// table valid) before anything is measured.
void check_outputs(const fs::path& dir) {
  io::check_output_folder(dir);
  io::check_output_path(dir / "costs.json");
  io::check_output_path(dir / "gpu_costs.md");
  // Its GPU section is replaced whatever it holds (e.g. rows of an older gpucost).
  cost::read_existing_cost_table(dir / "costs.json", cost::GpuSection::skip);
}

// Writes both outputs as one unit (io::write_files_atomic): both or neither.
void write_outputs(const cost::gpu::Report& report, const fs::path& dir) {
  const fs::path table_path = dir / "costs.json";
  std::optional<cost::CostTable> table =
      cost::read_existing_cost_table(table_path, cost::GpuSection::skip);
  if (!table) {
    // No CPU measurements yet: a table holding only the GPU section.
    table.emplace();
    table->info = cost::current_cost_table_info();
    table->info.command = "(no CPU costs: run `sglab bench --out DIR`)";
  }
  table->gpu = report;
  io::write_files_atomic(
      {{table_path, cost::to_json(*table).dump(2) + "\n"},
       {dir / "gpu_costs.md",
        fmt::format(
            "# GPU cost: ACO statistics on RADV null devices\n\n"
            "Driver: {}. Command: `{}`. Each figure is the function's own: the method in its "
            "harness minus the same harness around a trivial body (VGPRs and SGPRs: the "
            "whole pipeline's). Every harness is dispatched in whole workgroups, so the "
            "method's call is in no branch (ACO's estimate counts the code under a "
            "divergent branch at 0.75 of its cost). Inverse throughput is ACO's estimate of "
            "the cycles one wave keeps a SIMD busy, not a timing. Compile path: none "
            "(glslang's SPIR-V), legalized (HLSL: SPIRV-Tools' legalization passes), "
            "optimized (SPIRV-Tools' performance passes, after legalization for HLSL). A "
            "method's GLSL and HLSL exports are the same code with the same control flow "
            "(a conditional with a costly arm is an if, never ?:, which glslang's HLSL "
            "front end evaluates on both sides; one return per function, so that the "
            "legalization's merge-return leaves the branches ACO keeps); "
            "OnRadv.HlslCostsWhatGlslCosts holds their inverse throughputs within 5% on "
            "navi21 and gfx1100, unoptimized and legalized.\n\n{}",
            report.driver, report.command, cost::gpu::to_markdown(report))}});
}

// The (method, split) pairs to cost: unsplit rows for every method, then
// split rows for those with a split form (as --form asks).
std::vector<std::pair<std::string, bool>> costed_forms(const GpucostArgs& a,
                                                       const std::vector<std::string>& methods) {
  const auto split_ids = shader::split_methods();
  std::vector<std::pair<std::string, bool>> forms;
  for (bool split : {false, true})
    for (const std::string& m : methods)
      if ((split ? a.form != "unsplit" : a.form != "split") &&
          (!split || std::find(split_ids.begin(), split_ids.end(), m) != split_ids.end()))
        forms.emplace_back(m, split);
  return forms;
}

struct Plan {
  std::vector<std::string> methods;
  std::vector<shader::Language> languages;
  std::vector<shader::Precision> precisions;
  std::vector<cost::gpu::Harness> harnesses;
  std::vector<int> lights;
  std::vector<cost::gpu::CompilePath> compiles;
};

// Every shader of the plan, each baseline before its methods, harness-major
// (so each family's rows come in one section per harness): single for every
// precision, then loop and setup (float only, as the split export).
template <class Visit>
void for_each_shader(const GpucostArgs& a, const Plan& p, Visit&& visit) {
  const auto forms = costed_forms(a, p.methods);
  const auto split_ids = shader::split_methods();
  for (cost::gpu::Harness harness : p.harnesses)
    for (shader::Language lang : p.languages)
      for (cost::gpu::CompilePath compile : p.compiles) {
        if (!applies(compile, lang)) continue;
        if (harness == cost::gpu::Harness::single) {
          for (shader::Precision precision : p.precisions) {
            visit([=] { return gpu::baseline_shader(lang, precision, harness, 1, compile); }, "");
            for (const auto& [m, split] : forms) {
              if (split && precision == shader::Precision::float16) continue;
              visit(
                  [=, m = m, split = split] {
                    return split ? gpu::split_method_shader(m, lang, compile)
                                 : gpu::method_shader(m, lang, precision, compile);
                  },
                  fmt::format("{}{} ({}, {}, {})", m, split ? " --split" : "",
                              shader::to_string(lang), shader::to_string(precision),
                              cost::gpu::to_string(compile)));
            }
          }
        } else if (std::find(p.precisions.begin(), p.precisions.end(),
                             shader::Precision::float32) != p.precisions.end()) {
          if (harness == cost::gpu::Harness::loop) {
            for (int n : p.lights) {
              visit(
                  [=] {
                    return gpu::baseline_shader(lang, shader::Precision::float32, harness, n,
                                                compile);
                  },
                  "");
              for (const auto& [m, split] : forms)
                visit([=, m = m,
                       split = split] { return gpu::loop_shader(m, lang, split, n, compile); },
                      fmt::format("{}{} in a {}-light loop ({}, {})", m, split ? " --split" : "", n,
                                  shader::to_string(lang), cost::gpu::to_string(compile)));
            }
          } else if (a.form != "unsplit") {
            visit(
                [=] {
                  return gpu::baseline_shader(lang, shader::Precision::float32, harness, 1,
                                              compile);
                },
                "");
            for (const std::string& m : p.methods)
              if (std::find(split_ids.begin(), split_ids.end(), m) != split_ids.end())
                visit([=] { return gpu::setup_shader(m, lang, compile); },
                      fmt::format("{} setup ({}, {})", m, shader::to_string(lang),
                                  cost::gpu::to_string(compile)));
          }
        }
      }
}

// Measures (or with --disasm disassembles) and prints / writes the results.
// Throws gpu::Unavailable when RADV cannot create a null device.
void measure_and_report(const GpucostArgs& a, const std::vector<std::string>& families,
                        const Plan& p) {
  std::size_t count = 0;
  for_each_shader(a, p, [&](auto&&, const std::string&) { ++count; });
  if (count == 0)
    throw InputError(
        "gpucost: nothing to cost (the loop and setup harnesses are float only, the setup is the "
        "split form's, legalization is HLSL's)");
  const auto [self, manifest] = gpu::worker_setup("gpucost");
  if (a.disasm) {
    const bool split = a.form == "split";
    const shader::Language lang = p.languages[0];
    const cost::gpu::CompilePath compile = p.compiles[0];
    const cost::gpu::Harness harness = p.harnesses[0];
    gpu::Shader s;
    std::string what;
    switch (harness) {
      case cost::gpu::Harness::single:
        s = split ? gpu::split_method_shader(p.methods[0], lang, compile)
                  : gpu::method_shader(p.methods[0], lang, p.precisions[0], compile);
        what = split ? "one float load, the light struct at the workgroup's index, one float store"
                     : "one float2 load, one float store";
        break;
      case cost::gpu::Harness::loop:
        s = gpu::loop_shader(p.methods[0], lang, split, p.lights[0], compile);
        what =
            fmt::format("a per-pixel loop over {} lights, one normal per invocation", p.lights[0]);
        break;
      case cost::gpu::Harness::setup:
        s = gpu::setup_shader(p.methods[0], lang, compile);
        what = "the per-light setup: one kappa in, one light struct out";
        break;
    }
    std::string options;
    if (split && harness != cost::gpu::Harness::setup) options += " --form split";
    if (p.precisions[0] == shader::Precision::float16) options += " --precision half";
    if (harness != cost::gpu::Harness::single)
      options += fmt::format(" --harness {}", cost::gpu::to_string(harness));
    if (harness == cost::gpu::Harness::loop) options += fmt::format(" --lights {}", p.lights[0]);
    if (compile != cost::gpu::CompilePath::none)
      options += fmt::format(" --compile {}", cost::gpu::to_string(compile));
    fmt::print(
        "; sglab gpucost --disasm --method {} --family {} --lang {}{}\n; ACO's final assembly of "
        "the whole pipeline: the harness ({}) around the export\n{}",
        p.methods[0], families[0], shader::to_string(lang), options, what,
        gpu::disassemble(self, manifest, families[0], s));
    return;
  }
  io::Progress progress("gpucost", families.size() + count);
  std::vector<gpu::Shader> shaders;
  for_each_shader(a, p, [&](auto&& make, const std::string& note) {
    if (!note.empty()) progress.note("export " + note);
    shaders.push_back(make());
    progress.advance();
  });
  cost::gpu::Report report =
      gpu::measure(self, manifest, families, shaders, [&](std::string_view family) {
        progress.note(fmt::format("ACO, {}", family));
        progress.advance();
      });
  progress.finish();
  report.command = command_line(a);
  if (!a.out.empty()) write_outputs(report, a.out);
  if (a.json)
    fmt::print("{}\n", cost::gpu::to_json(report).dump(2));
  else
    fmt::print(
        "GPU cost from {} (ACO statistics; inverse throughput in cycles per wave, a compiler "
        "estimate). Command: `{}`\n\n{}",
        report.driver, report.command, cost::gpu::to_markdown(report));
}

}  // namespace

void add_gpucost_command(CLI::App& app) {
  auto args = std::make_shared<GpucostArgs>();
  auto* cmd = app.add_subcommand("gpucost",
                                 "GPU cost of every exported method from AMD's shader compiler "
                                 "(ACO on Mesa's RADV null devices)");
  cmd->add_option("--families,--family", args->families,
                  "comma-separated AMD chips (RADV_FORCE_FAMILY names; default "
                  "polaris10,vega10,navi10,navi21,gfx1100)");
  cmd->add_option("--method", args->methods,
                  "method id (repeatable; default every exportable method)");
  cmd->add_option("--lang", args->lang, "glsl, hlsl or both")->capture_default_str();
  cmd->add_option("--form", args->form,
                  "unsplit, split (the per-pixel function of `sglab export --split`, rows with "
                  "split = true, for the methods that have one) or both")
      ->capture_default_str();
  cmd->add_option(
         "--precision", args->precision,
         "float, half (`sglab export --precision half`, rows with precision \"half\") or both")
      ->capture_default_str();
  cmd->add_option("--harness", args->harnesses,
                  "comma-separated harnesses: single (one call per invocation), loop (a "
                  "renderer's per-pixel loop over --lights lights), setup (the split form's "
                  "per-light setup); default all three")
      ->delimiter(',');
  cmd->add_option("--lights", args->lights,
                  "comma-separated light counts of the loop harness, 1 to 64 (default 8, the "
                  "figure of --cost gpu:FAMILY)")
      ->delimiter(',');
  cmd->add_option("--compile", args->compiles,
                  "comma-separated compile paths: none (glslang's SPIR-V), legalized (HLSL: "
                  "spirv-opt's legalization), optimized (spirv-opt -O, after legalization for "
                  "HLSL); default none")
      ->delimiter(',');
  cmd->add_flag("--json", args->json, "print the rows as JSON on stdout");
  add_path_option(cmd, "--out", args->out,
                  "write DIR/gpu_costs.md and the \"gpu\" section of DIR/costs.json");
  cmd->add_flag("--skip-unavailable", args->skip_unavailable,
                "when RADV cannot create a null device, say why and exit 0 without writing "
                "anything (sglab run)");
  cmd->add_flag("--disasm", args->disasm,
                "print ACO's assembly of one method (--method ID --family F [--lang glsl|hlsl] "
                "[--harness H] [--lights N] [--compile C]) instead of the table");
  cmd->add_option("--worker-family", args->worker_family)->group("");
  cmd->add_option("--worker-dir", args->worker_dir)->group("");
  cmd->callback([args] {
    if (!args->worker_family.empty()) {
      gpu::run_worker(args->worker_family, args->worker_dir);
      return;
    }
    const auto families = checked_families(args->families);
    if (!args->out.empty()) check_outputs(args->out);
    const auto languages = checked_languages(args->lang);
    const auto methods = checked_methods(args->methods);
    if (args->form != "unsplit" && args->form != "split" && args->form != "both")
      throw InputError(fmt::format("--form: expected unsplit, split or both, got '{}'",
                                   args->form.substr(0, 40)));
    if (args->form == "split") {
      const auto split = shader::split_methods();
      for (const std::string& m : methods)
        if (std::find(split.begin(), split.end(), m) == split.end() && !args->methods.empty())
          throw InputError(
              fmt::format("--form split: method '{}' has no per-light split; methods with one: {}",
                          m, fmt::join(split, ", ")));
    }
    const auto precisions = checked_precisions(args->precision);
    // --disasm prints one shader: by default the single harness's.
    auto harnesses = checked_harnesses(args->harnesses);
    if (args->disasm && args->harnesses.empty()) harnesses = {cost::gpu::Harness::single};
    const auto lights = checked_lights(args->lights);
    const auto compiles = checked_compiles(args->compiles, languages);
    if (!args->lights.empty() &&
        std::find(harnesses.begin(), harnesses.end(), cost::gpu::Harness::loop) == harnesses.end())
      throw InputError("--lights: applies to the loop harness only (--harness loop)");
    if (args->form == "split" && args->precision == "half")
      throw InputError(
          "--form split with --precision half: the per-light split export is float only (its light "
          "struct is std430 floats filled by the float runtime); use --precision float");
    if (args->disasm &&
        (args->methods.size() != 1 || args->families.empty() || families.size() != 1 ||
         languages.size() != 1 || precisions.size() != 1 || harnesses.size() != 1 ||
         compiles.size() != 1 || (harnesses[0] == cost::gpu::Harness::loop && lights.size() != 1) ||
         args->json || !args->out.empty()))
      throw InputError(
          "--disasm: takes one --method, one --family, one --lang (glsl or hlsl), one "
          "--precision, one --harness (default single), with loop one --lights, and one "
          "--compile, and no --json or --out (--form split: the split export)");
    try {
      measure_and_report(*args, families,
                         {methods, languages, precisions, harnesses, lights, compiles});
    } catch (const gpu::Unavailable& e) {
      if (!args->skip_unavailable) throw;
      fmt::print(stderr, "sglab: gpucost skipped: {}\n", e.what());
    }
  });
}

}  // namespace sglab::app
