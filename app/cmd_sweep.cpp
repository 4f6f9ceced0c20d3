// `sglab sweep`: every method against the reference over the SPEC §4 grid (or
// a custom one), in float and double, with the SPEC §3 metrics. Writes the
// summary, per-κ and per-point tables into --out and prints the summary.
#include <algorithm>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "args.hpp"
#include "commands.hpp"
#include "io.hpp"
#include "sweep.hpp"
#include "table.hpp"

namespace sglab::app {

namespace {

bool parse_int(std::string_view s, int& out) {
  if (s.empty()) return false;
  const char* begin = s.data();
  if (*begin == '+') ++begin;  // from_chars rejects a leading '+'
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(begin, end, out);
  return ec == std::errc() && ptr == end;
}

// --kappa LO:HI:N (validate/args.hpp; float: the sweep rounds its inputs to float)
void parse_kappa_option(const std::string& text, validate::SweepGrid& grid) {
  validate::KappaRangeRules rules;
  rules.with_count = true;
  const auto parsed = validate::parse_kappa_range(text, rules);
  if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--kappa: " + *why);
  const auto& r = std::get<validate::KappaRange>(parsed);
  grid.kappa_lo = r.lo;
  grid.kappa_hi = r.hi;
  grid.kappa_count = r.count;
}

void parse_cosines_option(const std::string& text, validate::SweepGrid& grid) {
  int n = 0;
  if (!parse_int(text, n)) throw InputError(fmt::format("--cosines: '{}' is not an integer", text));
  if (n < 2) throw InputError(fmt::format("--cosines: must be >= 2 (the grid includes c = -1 and c = 1), got {}", n));
  grid.cosine_count = n;
}

std::vector<validate::SweepMethod> select_methods(const std::vector<std::string>& ids) {
  auto all = validate::registered_sweep_methods();
  if (ids.empty()) return all;
  std::vector<std::string> known;
  for (const auto& m : all)
    if (std::find(known.begin(), known.end(), m.method.id) == known.end()) known.emplace_back(m.method.id);
  for (const std::string& id : ids)
    if (std::find(known.begin(), known.end(), id) == known.end())
      throw InputError(fmt::format("--method: unknown method id '{}'; known ids: {}", id, fmt::join(known, ", ")));
  std::vector<validate::SweepMethod> out;
  for (const auto& m : all)
    if (std::find(ids.begin(), ids.end(), m.method.id) != ids.end()) out.push_back(m);
  return out;
}

struct SweepArgs {
  std::string kappa;
  std::string cosines;
  std::string out = "out/sweep";
  bool json = false;
  std::vector<std::string> methods;
};

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand(
      "sweep", "Accuracy of every method against the reference over a (κ, c) grid, in float and double");
  cmd->add_option("--kappa", args->kappa,
                  "κ grid LO:HI:N, N values log-spaced over [LO, HI] (default: SPEC §4, 1e-3:1e4:29)");
  cmd->add_option("--cosines", args->cosines, "number of cosines evenly spaced over [-1, 1] (default 41)");
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_flag("--json", args->json, "print the summary as JSON on stdout");
  cmd->add_option("--method", args->methods, "restrict to this method id (repeatable)");
  cmd->callback([args] {
    validate::SweepGrid grid;  // SPEC §4 standard grid
    if (!args->kappa.empty()) parse_kappa_option(args->kappa, grid);
    if (!args->cosines.empty()) parse_cosines_option(args->cosines, grid);
    try {
      grid.validate();
    } catch (const std::invalid_argument& e) {
      throw InputError(e.what());
    }
    const auto methods = select_methods(args->methods);

    const validate::SweepResult result = validate::sweep(grid, methods);
    const validate::Table summary = validate::summary_table(result);
    const std::filesystem::path dir(args->out);
    using validate::TableFormat;
    validate::write_table(summary, dir, "summary", {TableFormat::csv, TableFormat::markdown});
    validate::write_table(validate::per_kappa_table(result), dir, "per_kappa",
                          {TableFormat::csv, TableFormat::markdown});
    validate::write_table(validate::points_table(result), dir, "points", {TableFormat::csv});

    nlohmann::ordered_json doc = nlohmann::ordered_json::object();
    doc["grid"] = {{"kappa_lo", grid.kappa_lo},
                   {"kappa_hi", grid.kappa_hi},
                   {"kappa_count", grid.kappa_count},
                   {"cosine_count", grid.cosine_count}};
    doc["results"] = validate::to_json_records(summary);
    const std::string json = doc.dump(2) + "\n";
    io::write_file_atomic(dir / "summary.json", json);

    if (args->json)
      fmt::print("{}", json);
    else
      fmt::print("{}\nWritten to {}: summary.{{csv,md,json}}, per_kappa.{{csv,md}}, points.csv\n",
                 validate::to_markdown(summary), dir.string());
  });
}

}  // namespace sglab::app
