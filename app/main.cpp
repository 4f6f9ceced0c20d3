// sglab — spherical Gaussian diffuse lighting: fit, validate, compare.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sglab: refit, validate and compare spherical Gaussian diffuse lighting methods"};
  app.require_subcommand(1);
  sglab::app::add_methods_command(app);
  sglab::app::add_table_command(app);
  sglab::app::add_constants_command(app);
  sglab::app::add_fit_command(app);
  sglab::app::add_run_command(app);
  sglab::app::add_erf_command(app);
  sglab::app::add_sweep_command(app);
  sglab::app::add_stability_command(app);
  sglab::app::add_reference_command(app);
  sglab::app::add_figures_command(app);
  sglab::app::add_claims_command(app);
  sglab::app::add_bench_command(app);
  sglab::app::add_pareto_command(app);
  sglab::app::add_recommend_command(app);
  sglab::app::add_eval_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const sglab::app::InputError& e) {
    fmt::print(stderr, "sglab: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "sglab: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
