// `sglab constants`: list the constant sets of data/constants/*.json, or
// regenerate include/sglab/constants.hpp from them.
#include <fmt/format.h>

#include "commands.hpp"
#include "constants_io.hpp"

namespace sglab::app {

void add_constants_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("constants", "List the constant sets, or regenerate the runtime header from them");
  auto dir = std::make_shared<std::string>(fit::default_constants_dir().string());
  auto header = std::make_shared<std::string>(fit::default_header_path().string());
  auto write = std::make_shared<bool>(false);
  cmd->add_option("--dir", *dir, "directory of constant-set JSON files")->capture_default_str();
  cmd->add_option("--header", *header, "header to write with --write-header")->capture_default_str();
  cmd->add_flag("--write-header", *write, "regenerate the header from the JSON files");
  cmd->callback([dir, header, write] {
    std::vector<fit::ordered_json> sets;
    try {
      sets = fit::load_constant_sets(*dir);
    } catch (const std::runtime_error& e) {
      throw InputError(e.what());
    }
    if (*write) {
      fit::write_constants_header(*dir, *header);
      fmt::print("wrote {} ({} constant sets)\n", *header, sets.size());
      return;
    }
    for (const auto& set : sets) {
      fmt::print("{:<32} {:<14} {}\n", set["cpp_name"].get<std::string>(),
                 set["provenance"].value("objective", std::string("?")), set["coefficients"].dump());
    }
  });
}

}  // namespace sglab::app
