// `sglab methods` prints every registered method's card (text, JSON or Markdown); `sglab table`
// prints every irradiance method at one κ over a few cosines, beside the reference.
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "reference/reference.hpp"
#include "validate/kappa_range.hpp"

namespace sglab::app {

namespace {

// The constant sets of a card, "a, b" -> ["a", "b"].
nlohmann::ordered_json constant_sets(std::string_view text) {
  nlohmann::ordered_json sets = nlohmann::ordered_json::array();
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t comma = text.find(',', start);
    if (comma == std::string_view::npos) comma = text.size();
    std::string_view name = text.substr(start, comma - start);
    while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    if (!name.empty()) sets.push_back(std::string(name));
    start = comma + 1;
  }
  return sets;
}

// {"irradiance": [card...], "hemispherical": [...], "normalized": [...], "erf": [{id, source}]},
// a card {id, origin, source, summary, form, constants: [...], per_light_split, half,
// valid_range}.
nlohmann::ordered_json methods_json() {
  auto list = [](std::span<const Method> methods) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const Method& m : methods)
      a.push_back(
          {{"id", std::string(m.id)},
           {"origin", std::string(to_string(m.origin))},
           {"source", std::string(m.source)},
           {"summary", std::string(m.summary)},
           {"form", std::string(m.form)},
           {"constants", constant_sets(m.constants)},
           {"per_light_split", m.has_split()},
           {"half", std::string(m.half)},
           {"valid_range", m.valid.max_peak_rel > 0
                               ? nlohmann::ordered_json{{"max_peak_rel", m.valid.max_peak_rel},
                                                        {"kappa_lo", m.valid.kappa_lo},
                                                        {"kappa_hi", m.valid.kappa_hi}}
                               : nlohmann::ordered_json(nullptr)}});
    return a;
  };
  nlohmann::ordered_json out;
  out["irradiance"] = list(irradiance_methods);
  out["hemispherical"] = list(hemispherical_methods);
  out["normalized"] = list(normalized_methods);
  out["erf"] = nlohmann::ordered_json::array();
  for (const ErfVariant& v : erf_variants)
    out["erf"].push_back({{"id", std::string(v.id)}, {"source", std::string(v.source)}});
  return out;
}

// Text for one Markdown table cell: '|' escaped, empty as "–".
std::string cell(std::string_view text) {
  if (text.empty()) return "–";
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += '\\';
    out += ch;
  }
  return out;
}

// The cards as Markdown tables: irradiance, then the hemispherical integrals, then erf.
void print_methods_markdown() {
  fmt::print(
      "| method | origin | what | form | source | constants | per-light split | own half form | "
      "bound (max peak_rel) | valid κ |\n"
      "|---|---|---|---|---|---|---|---|---:|---|\n");
  for (const Method& m : irradiance_methods)
    fmt::print("| `{}` | {} | {} | {} | {} | {} | {} | {} | {:.2g} | {} |\n", m.id,
               to_string(m.origin), cell(m.summary), cell(m.form), cell(m.source),
               cell(m.constants), m.has_split() ? "yes" : "no", cell(m.half), m.valid.max_peak_rel,
               validate::kappa_range_text(m.valid));
  fmt::print(
      "\n| hemispherical H̃ and normalized s̃ | what | source | constants |\n"
      "|---|---|---|---|\n");
  for (const Method& m : hemispherical_methods)
    fmt::print("| `{}` | {} | {} | {} |\n", m.id, cell(m.summary), cell(m.source),
               cell(m.constants));
  fmt::print("\n| erf variant | source |\n|---|---|\n");
  for (const ErfVariant& v : erf_variants) fmt::print("| `{}` | {} |\n", v.id, cell(v.source));
}

}  // namespace

void add_methods_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "methods", "List every method's registry card: id, origin, source, form, constants");
  auto format = std::make_shared<std::string>("text");
  cmd->add_option("--format", *format,
                  "text, json (every card: id, origin, source, summary, form, constant sets, "
                  "per-light split, half form, valid κ range) or md (the cards as Markdown tables)")
      ->check(CLI::IsMember({"text", "json", "md"}))
      ->capture_default_str();
  cmd->add_flag_callback(
      "--json", [format] { *format = "json"; }, "the same as --format json");
  cmd->callback([format] {
    if (*format == "json") {
      fmt::print("{}\n", methods_json().dump(2));
      return;
    }
    if (*format == "md") {
      print_methods_markdown();
      return;
    }
    auto list = [](const char* title, std::span<const Method> methods) {
      fmt::print("{}:\n", title);
      for (const Method& m : methods)
        fmt::print("  {:<22} {} ({}){}{}\n", m.id, m.summary, m.source,
                   m.constants.empty() ? "" : fmt::format(" [{}]", m.constants),
                   m.valid.max_peak_rel > 0
                       ? fmt::format("; max peak_rel ≤ {:.2g} for κ in {}", m.valid.max_peak_rel,
                                     validate::kappa_range_text(m.valid))
                       : std::string());
    };
    list("irradiance", irradiance_methods);
    list("hemispherical", hemispherical_methods);
    fmt::print("erf:\n");
    for (const ErfVariant& v : erf_variants) fmt::print("  {:<22} {}\n", v.id, v.source);
  });
}

void add_table_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "table", "Print every irradiance method at one sharpness over a few cosines");
  auto kappa = std::make_shared<double>(4.0);
  auto count = std::make_shared<int>(9);
  cmd->add_option("--kappa", *kappa, "SG sharpness κ (≥ 0)")->capture_default_str();
  cmd->add_option("--cosines", *count, "number of cosines, evenly spaced over [-1, 1] (≥ 2)")
      ->check(count_in(2, std::numeric_limits<int>::max()))
      ->capture_default_str();
  cmd->callback([kappa, count] {
    if (!(std::isfinite(*kappa) && *kappa >= 0))
      throw InputError(fmt::format("--kappa must be finite and >= 0, got {}", *kappa));
    std::vector<reference::Query> queries;
    for (int i = 0; i < *count; ++i) queries.push_back({*kappa, -1.0 + 2.0 * i / (*count - 1)});
    const auto ref = reference::reference_engine().evaluate(queries);
    fmt::print(
        "Irradiance E(c, κ) of a unit-amplitude SG light, κ = {} (double precision); last column: "
        "max |Ê − E|/E(1, κ)\n\n",
        *kappa);
    fmt::print("| {:<22} |", "method \\ cosine");
    // Values in %.4e: five significant digits at every κ (E(c, κ) ≈ 2π/κ is
    // small for sharp lights, and a fixed number of decimals would print 0).
    for (const auto& r : ref) fmt::print(" {:>11.3f} |", r.cosine);
    fmt::print(" {:>9} |\n|:{:-<22}-|", "peak_rel", "");
    for (std::size_t i = 0; i < ref.size(); ++i) fmt::print("{:-<12}:|", "");
    fmt::print("{:-<10}:|", "");
    fmt::print("\n| {:<22} |", "reference");
    for (const auto& r : ref) fmt::print(" {:>11.4e} |", r.irradiance);
    fmt::print(" {:>9} |\n", "");
    const double peak = ref.back().irradiance;  // c = 1
    for (const Method& m : irradiance_methods) {
      fmt::print("| {:<22} |", m.id);
      double worst = 0;
      for (const auto& r : ref) {
        const double v = m.f64(r.cosine, r.kappa);
        const double err = std::abs(v - r.irradiance) / peak;
        worst = std::isnan(err) || std::isnan(worst) ? std::nan("") : std::max(worst, err);
        fmt::print(" {:>11.4e} |", v);
      }
      fmt::print(" {:>9.2e} |\n", worst);
    }
  });
}

}  // namespace sglab::app
