// cost/gpu_report.cpp — see gpu_report.hpp.
#include "cost/gpu_report.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace sglab::cost::gpu {

using json = nlohmann::ordered_json;

Statistics subtract(const Statistics& measured, const Statistics& baseline) {
  Statistics s = measured;
  for (const StatisticField& f : kStatisticFields)
    if (f.additive) s.*f.member -= baseline.*f.member;
  return s;
}

json to_json(const Statistics& s) {
  json j;
  for (const StatisticField& f : kStatisticFields) j[f.json_key] = s.*f.member;
  return j;
}

Statistics statistics_from_json(const json& j, const std::string& where) {
  Statistics s;
  for (const StatisticField& f : kStatisticFields) {
    if (!j.is_object() || !j.contains(f.json_key) || !j.at(f.json_key).is_number_integer())
      throw std::runtime_error(fmt::format("{}.{}: must be an integer", where, f.json_key));
    s.*f.member = j.at(f.json_key).get<std::int64_t>();
  }
  return s;
}

double cycles_per_light(const Row& r) {
  return static_cast<double>(r.stats.inverse_throughput) / r.lights;
}

namespace {

const Row* find_row(const Report& report, std::string_view method, std::string_view family,
                    Harness harness, int lights, bool split) {
  for (const Row& r : report.rows)
    if (r.method == method && r.family == family && r.lang == io::Language::glsl &&
        r.compile == CompilePath::none && r.precision == "float" && r.harness == harness &&
        r.lights == lights && r.split == split)
      return &r;
  return nullptr;
}

}  // namespace

const Row* renderer_row(const Report& report, std::string_view method, std::string_view family) {
  if (const Row* split = find_row(report, method, family, Harness::loop, kRendererLights, true))
    return split;
  return find_row(report, method, family, Harness::loop, kRendererLights, false);
}

const Row* single_row(const Report& report, std::string_view method, std::string_view family) {
  return find_row(report, method, family, Harness::single, 1, false);
}

std::string renderer_form(const Row& r) {
  return fmt::format("{}-light loop ({})", r.lights, r.split ? "split" : "kappa per light");
}

json to_json(const Report& report) {
  json j;
  j["driver"] = report.driver;
  j["command"] = report.command;
  j["harnesses"] =
      "each row: the method in its harness minus the same harness around a trivial body (vgprs "
      "and sgprs: the whole pipeline's); every harness is dispatched in whole workgroups of 64, "
      "so no bounds check puts the call in a branch. single: one call per invocation ((cosine, "
      "kappa) loaded, the value stored; split: one float load, the light struct at the "
      "workgroup's index, one store), minus the same wrapper around `return cosine + kappa;`: "
      "the struct's loads count as the function's. loop: a renderer's per-pixel loop, one normal "
      "per invocation, `lights` lights written out (axis and amplitude, and kappa or the split "
      "struct, at wave-uniform indices), the irradiance summed, minus the same loop around "
      "`return cosine + kappa;` with kappa per light: the figures are those of all the lights "
      "(cycles per light per pixel = inverse_throughput / lights). setup: the split form's "
      "per-light setup, one kappa in and one struct out per invocation, minus the same kernel "
      "filling a struct of kappa alone. compile: none (glslang's SPIR-V), legalized (HLSL, "
      "SPIRV-Tools' legalization passes), optimized (SPIRV-Tools' performance passes, after "
      "legalization for HLSL)";
  j["rows"] = json::array();
  for (const Row& r : report.rows) {
    json row = {{"method", r.method},
                {"family", r.family},
                {"lang", std::string(io::to_string(r.lang))},
                {"compile", std::string(to_string(r.compile))},
                {"harness", std::string(to_string(r.harness))},
                {"lights", r.lights},
                {"split", r.split},
                {"precision", r.precision}};
    row.update(to_json(r.stats));
    row["spirv_hash"] = r.spirv_hash;
    j["rows"].push_back(std::move(row));
  }
  return j;
}

Report report_from_json(const json& j, std::string_view where) {
  const auto text = [&](const json& obj, const char* key, const std::string& at) {
    if (!obj.is_object() || !obj.contains(key) || !obj.at(key).is_string())
      throw std::runtime_error(fmt::format("{}: {}{} must be a string", where, at, key));
    return obj.at(key).get<std::string>();
  };
  Report r;
  r.driver = text(j, "driver", "");
  r.command = text(j, "command", "");
  if (!j.contains("rows") || !j.at("rows").is_array())
    throw std::runtime_error(fmt::format("{}: rows must be an array", where));
  std::size_t i = 0;
  for (const json& row : j.at("rows")) {
    const std::string at = fmt::format("rows[{}].", i++);
    Row x;
    x.method = text(row, "method", at);
    x.family = text(row, "family", at);
    const auto lang = io::parse_enum<io::Language>(text(row, "lang", at));
    if (!lang || *lang == io::Language::cpp)
      throw std::runtime_error(fmt::format("{}: {}lang must be glsl or hlsl", where, at));
    x.lang = *lang;
    if (!row.contains("harness"))
      throw std::runtime_error(fmt::format(
          "{}: {}harness is missing: a row of an older `sglab gpucost`, whose harness put the "
          "call inside a bounds check (a discount of about a quarter); rerun `sglab gpucost "
          "--out DIR`",
          where, at));
    const auto compile = io::parse_enum<CompilePath>(text(row, "compile", at));
    if (!compile || (*compile == CompilePath::legalized && x.lang != io::Language::hlsl))
      throw std::runtime_error(
          fmt::format("{}: {}compile must be none, legalized (HLSL only) or optimized", where, at));
    x.compile = *compile;
    const auto harness = io::parse_enum<Harness>(text(row, "harness", at));
    if (!harness)
      throw std::runtime_error(
          fmt::format("{}: {}harness must be single, loop or setup", where, at));
    x.harness = *harness;
    if (!row.contains("lights") || !row.at("lights").is_number_integer() ||
        row.at("lights").get<std::int64_t>() < 1 ||
        row.at("lights").get<std::int64_t>() > kMaxLights ||
        (x.harness != Harness::loop && row.at("lights").get<std::int64_t>() != 1))
      throw std::runtime_error(
          fmt::format("{}: {}lights must be an integer from 1 to {} (1 outside the loop harness)",
                      where, at, kMaxLights));
    x.lights = row.at("lights").get<int>();
    if (!row.contains("split") || !row.at("split").is_boolean())
      throw std::runtime_error(fmt::format("{}: {}split must be true or false", where, at));
    x.split = row.at("split").get<bool>();
    x.precision = text(row, "precision", at);
    if (x.precision != "float" && x.precision != "half")
      throw std::runtime_error(fmt::format("{}: {}precision must be float or half", where, at));
    x.stats = statistics_from_json(row, fmt::format("{}: {}", where, at.substr(0, at.size() - 1)));
    x.spirv_hash = text(row, "spirv_hash", at);
    r.rows.push_back(std::move(x));
  }
  return r;
}

std::string to_markdown(const Report& report) {
  std::string out;
  std::string family;
  int section = -1;
  for (const Row& r : report.rows) {
    if (r.family != family) {
      family = r.family;
      section = -1;
      std::string generation;
      for (const Family& f : kDefaultFamilies)
        if (family == f.name) generation = fmt::format(" ({})", f.generation);
      out += fmt::format("{}## {}{}\n", out.empty() ? "" : "\n", family, generation);
    }
    if (static_cast<int>(r.harness) != section) {
      section = static_cast<int>(r.harness);
      switch (r.harness) {
        case Harness::single:
          out += "\nOne call per invocation (harness `single`):\n\n";
          break;
        case Harness::loop:
          out +=
              "\nA renderer's per-pixel loop over N lights (harness `loop`; the statistics are "
              "those of all N lights, cycles per light = inverse throughput / N):\n\n";
          break;
        case Harness::setup:
          out += "\nThe per-light setup of the split form as its own kernel (harness `setup`):\n\n";
          break;
      }
      out += fmt::format(
          "| method | lang | compile |{} instructions | inverse throughput |{} latency | VGPRs | "
          "SGPRs | code size | branches |\n|---|---|---|{}---:|---:|{}---:|---:|---:|---:|---:|\n",
          r.harness == Harness::loop ? " N |" : "",
          r.harness == Harness::loop ? " cycles per light |" : "",
          r.harness == Harness::loop ? "---:|" : "", r.harness == Harness::loop ? "---:|" : "");
    }
    const std::string method =
        r.method + (r.harness != Harness::setup && r.split ? " (split)" : "");
    out += fmt::format(
        "| {} | {}{} | {} |{} {} | {} |{} {} | {} | {} | {} | {} |\n", method,
        io::to_string(r.lang), r.precision == "half" ? " half" : "", to_string(r.compile),
        r.harness == Harness::loop ? fmt::format(" {} |", r.lights) : "", r.stats.instructions,
        r.stats.inverse_throughput,
        r.harness == Harness::loop ? fmt::format(" {:.1f} |", cycles_per_light(r)) : "",
        r.stats.latency, r.stats.vgprs, r.stats.sgprs, r.stats.code_size, r.stats.branches);
  }
  return out;
}

}  // namespace sglab::cost::gpu
