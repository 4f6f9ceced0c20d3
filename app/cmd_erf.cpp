// `sglab erf`: every erf variant (docs/references.md) against the correctly rounded erf,
// in float and in double — max abs / ulp error, where, RMS, non-finite count
// and the ulp histogram, in the style of libm accuracy tables.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "report/erf_report.hpp"

namespace sglab::app {

namespace {

struct ErfArgs {
  std::vector<std::string> variants;
  bool exhaustive = false;
  bool json = false;
  std::string out;
  std::size_t bins = 2000;
  std::uint32_t double_points = 1'000'000;
  std::uint32_t tail_stride = 1;
};

std::string known_variants() {
  std::string s;
  for (const ErfVariant& v : erf_variants) s += (s.empty() ? "" : ", ") + std::string(v.id);
  return s;
}

// The functors of sglab/erf.hpp inline into the checker's loop; any other
// registry entry runs through its function pointers.
template <class Fn>
void with_erf_callables(const ErfVariant& v, Fn&& fn) {
  if (v.id == ErfListing5::id) return fn(ErfListing5{}, ErfListing5{});
  if (v.id == ErfAS7125::id) return fn(ErfAS7125{}, ErfAS7125{});
  if (v.id == ErfStd::id) return fn(ErfStd{}, ErfStd{});
  fn(v.f32, v.f64);
}

void run_erf(const ErfArgs& args) {
  std::vector<const ErfVariant*> selected;
  for (const std::string& id : args.variants) {
    const ErfVariant* v = find_erf_variant(id);
    if (!v)
      throw InputError(fmt::format("unknown erf variant '{}' (known: {})", id, known_variants()));
    if (std::find(selected.begin(), selected.end(), v) == selected.end()) selected.push_back(v);
  }
  if (args.variants.empty())
    for (const ErfVariant& v : erf_variants) selected.push_back(&v);
  if (args.bins < 1 || args.bins > 1'000'000)
    throw InputError(fmt::format("--bins must be in [1, 1000000], got {}", args.bins));
  if (args.tail_stride < 1) throw InputError("--tail-stride must be >= 1");
  if (args.double_points < 1024)
    throw InputError(fmt::format("--double-points must be >= 1024, got {}", args.double_points));

  reference::ErfDoubleOptions dopt;
  dopt.grid_points = args.double_points;
  dopt.bins = args.bins;
  const reference::ErfDoubleSample sample = reference::make_erf_double_sample(dopt);

  std::vector<validate::ErfReport> reports;
  for (const ErfVariant* v : selected) {
    validate::ErfFloatOptions fopt;
    fopt.exhaustive = args.exhaustive;
    fopt.bins = args.bins;
    // terminals only
    fopt.progress_label =
        fmt::format("erf {} float{}", v->id, args.exhaustive ? ", exhaustive" : "");
    if (args.exhaustive) {
      fopt.odd_stride = 127;  // negatives: 16.7 million sampled, not all
      fopt.exhaustive_tail_stride = args.tail_stride;
    }
    with_erf_callables(*v, [&](auto f32, auto f64) {
      reports.push_back(validate::check_erf_float(f32, fopt, v->id));
      reports.push_back(validate::check_erf_double(f64, sample, v->id));
    });
  }

  if (args.json)
    fmt::print("{}", report::erf_reports_json(reports, args.exhaustive));
  else
    fmt::print("{}", report::erf_reports_markdown(reports, args.exhaustive));

  if (!args.out.empty()) {
    const std::filesystem::path dir(args.out);
    for (const validate::ErfReport& r : reports)
      io::write_file_atomic(dir / fmt::format("erf_{}_{}.csv", r.variant, r.precision),
                            report::erf_series_csv(r));
    io::write_file_atomic(dir / "erf_summary.csv", report::erf_summary_csv(reports));
    io::write_file_atomic(dir / "erf_histogram.csv", report::erf_histogram_csv(reports));
    io::write_file_atomic(dir / "erf_summary.md",
                          report::erf_reports_markdown(reports, args.exhaustive));
    if (!args.json)
      fmt::print(
          "\nwrote {} series CSVs, erf_summary.csv, erf_histogram.csv, erf_summary.md to {}\n",
          reports.size(), dir.string());
  }
}

}  // namespace

void add_erf_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("erf",
                                 "Every erf variant against the correctly rounded erf, in float "
                                 "and double (max abs/ulp error, worst x, RMS, histogram)");
  auto args = std::make_shared<ErfArgs>();
  cmd->add_option("--variant", args->variants,
                  "erf variant id (repeatable; default: all of " + known_variants() + ")");
  cmd->add_flag(
      "--exhaustive", args->exhaustive,
      "float: every float in [0, 4] and every float from 4 to FLT_MAX (default: a dense sample)");
  cmd->add_flag("--json", args->json, "print the results as JSON on stdout instead of tables");
  add_path_option(cmd, "--out", args->out,
                  "directory for per-variant CSV series of the ulp error over x, the summary (CSV, "
                  "Markdown) and the histogram (CSV)");
  cmd->add_option("--tail-stride", args->tail_stride,
                  "with --exhaustive: check every N-th float bit pattern in [64, FLT_MAX] (every "
                  "float in [4, 64) always; 1 = every float)")
      ->check(count_in(1, std::numeric_limits<std::uint32_t>::max()))
      ->capture_default_str();
  cmd->add_option("--bins", args->bins, "bins of x in the CSV series")
      ->check(count_in(1, 1'000'000))
      ->capture_default_str();
  cmd->add_option("--double-points", args->double_points,
                  "uniform grid points of the double check over [0, 6)")
      ->check(count_in(1024, std::numeric_limits<std::uint32_t>::max()))
      ->capture_default_str();
  cmd->callback([args] { run_erf(*args); });
}

}  // namespace sglab::app
