// app/commands.hpp — the subcommands of the `sglab` executable. Each lives
// in its own app/cmd_<name>.cpp and registers itself on the root CLI11 app.
#pragma once

#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "common/args.hpp"
#include "common/io.hpp"
#include "export/shader_export.hpp"

namespace sglab::app {

// Bad input from the user (a malformed file, an out-of-range value): the
// message names what was wrong; the process exits with code 2. Defined in
// common/io.hpp, so that the readers and writers below app/ raise it too.
using InputError = io::InputError;

// The check of every path option, input or output (--out, --header, --dir,
// --costs, --constants, --maps, --points, --scene, a map FILE, ...): an empty
// name is refused (exit 2) rather than taken as the working directory, the
// checkout's default files or the compiled-in data.
inline CLI::Validator non_empty_path() {
  return CLI::Validator(
      [](std::string& value) {
        return value.empty() ? std::string("an empty path is not allowed") : std::string();
      },
      "PATH", "non-empty path");
}

// A path option of `cmd` (input or output), checked by non_empty_path().
template <class T>
CLI::Option* add_path_option(CLI::App* cmd, const std::string& name, T& value,
                             const std::string& description) {
  return cmd->add_option(name, value, description)->check(non_empty_path());
}

// --lang glsl|hlsl|both (gpucost, and the vulkan backend of sweep): the
// shader languages, glsl first.
inline std::vector<shader::Language> checked_languages(const std::string& lang) {
  if (lang == "glsl") return {shader::Language::glsl};
  if (lang == "hlsl") return {shader::Language::hlsl};
  if (lang == "both") return {shader::Language::glsl, shader::Language::hlsl};
  throw InputError(fmt::format("--lang: expected glsl, hlsl or both, got '{}'", lang));
}

// Parses with `parse()` (which runs the chosen subcommand's callback) and
// maps the outcome to the documented exit codes: 0 success (also --help,
// --version), 1 failure, 2 bad input (InputError, or any command-line error
// CLI11 finds). The one place where sglab's exit codes are decided.
template <class Parse>
int run_and_map_exit_code(CLI::App& app, Parse&& parse) {
  try {
    parse();
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const InputError& e) {
    fmt::print(stderr, "sglab: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "sglab: error: {}\n", e.what());
    return 1;
  }
  return 0;
}

// The check of every whole-number option: io::parse_count's rules
// (digits only, min ≤ value ≤ max), applied to the text before CLI11
// converts it, so "-1" is not wrapped to 18446744073709551615 and a value
// beyond the type says "out of range", not "not an integer".
inline CLI::Validator count_in(long long min, long long max) {
  return CLI::Validator(
      [min, max](std::string& value) {
        const auto parsed = io::parse_count(value, min, max);
        const auto* why = std::get_if<std::string>(&parsed);
        return why ? *why : std::string();
      },
      fmt::format("INT in [{} - {}]", min, max), "count");
}

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
void add_gpucost_command(CLI::App& app);
void add_envmap_command(CLI::App& app);
void add_range_command(CLI::App& app);

}  // namespace sglab::app
