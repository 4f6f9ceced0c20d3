// `sglab figures`: data CSVs, gnuplot scripts, PNG and SVG for the figures
// after the cited papers ([Tokuyoshi2022], [Pettineo2016]) and the sglab
// comparisons (validate/figures), plus index.md.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "cost/cost_table.hpp"
#include "fit/targets.hpp"
#include "report/figures.hpp"

namespace sglab::app {

namespace {
struct FiguresArgs {
  std::string out = "out/figures";
  std::vector<std::string> pareto = {"out/pareto/pareto.csv"};
  std::string costs;  // empty: the project's data/results/costs.json when there is one
  std::string gnuplot = "gnuplot";
};
}  // namespace

void add_figures_command(CLI::App& app) {
  auto args = std::make_shared<FiguresArgs>();
  auto* cmd = app.add_subcommand("figures",
                                 "Render the figures (data CSV + gnuplot PNG/SVG) and an index.md");
  add_path_option(cmd, "--out", args->out, "output directory")->capture_default_str();
  add_path_option(cmd, "--pareto", args->pareto,
                  "Pareto CSV written by `sglab pareto`, repeatable: figure e draws one panel per "
                  "cost source (--cost) in them, side by side (e.g. the GPU cost and the CPU batch "
                  "one; skipped when absent)")
      ->capture_default_str();
  add_path_option(cmd, "--costs", args->costs,
                  "cost table whose \"gpu\" section figure e tables beside a GPU panel (the other "
                  "families' inverse throughput; default: data/results/costs.json of the project "
                  "holding the working directory, if any)");
  add_path_option(cmd, "--gnuplot", args->gnuplot, "gnuplot executable")->capture_default_str();
  cmd->callback([args] {
    const auto start = std::chrono::steady_clock::now();
    report::FiguresOptions opt;
    opt.out = args->out;
    opt.pareto.assign(args->pareto.begin(), args->pareto.end());
    opt.gnuplot = args->gnuplot;
    if (!args->costs.empty())
      opt.gpu = cost::read_cost_table(args->costs).gpu;
    else if (const auto found = cost::default_cost_table_path())
      if (const auto table = cost::read_existing_cost_table(*found)) opt.gpu = table->gpu;
    opt.optimal_steepness = [](const std::vector<double>& kappas) {
      return fit::optimal_steepness("steepness2022", kappas);
    };
    std::vector<report::Figure> figs;
    try {
      figs = report::make_figures(opt);
    } catch (const report::GnuplotMissing& e) {
      throw std::runtime_error(e.what());
    } catch (const std::invalid_argument& e) {
      throw InputError(e.what());
    }
    for (const auto& f : figs) {
      if (f.skipped) {
        fmt::print("{:<22} {}\n", f.id, f.note);
        continue;
      }
      std::string files;
      for (const auto& p : f.files) {
        if (!files.empty()) files += ' ';
        files += p.string();
      }
      fmt::print("{:<22} {}\n", f.id, files);
      if (!f.note.empty()) fmt::print("{:<22} note: {}\n", "", f.note);
    }
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print("Written to {} (index.md) in {:.1f} s\n", opt.out.string(), s);
  });
}

}  // namespace sglab::app
