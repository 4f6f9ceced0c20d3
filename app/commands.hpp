// app/commands.hpp — the subcommands of the `sglab` executable. Each lives
// in its own app/cmd_<name>.cpp and registers itself on the root CLI11 app.
#pragma once

#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace sglab::app {

// Bad input from the user (a malformed file, an out-of-range value): the
// message names what was wrong; the process exits with code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void add_methods_command(CLI::App& app);
void add_table_command(CLI::App& app);
void add_constants_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_erf_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_stability_command(CLI::App& app);
void add_reference_command(CLI::App& app);
void add_figures_command(CLI::App& app);
void add_claims_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_pareto_command(CLI::App& app);
void add_recommend_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_eval_command(CLI::App& app);

}  // namespace sglab::app
