// `sglab constants`: list the constant sets of data/constants/*.json, or
// regenerate include/sglab/constants.hpp from them. The files are untrusted
// input: each is checked against fit/constants_schema.hpp, and a header is
// only written from a complete, valid collection.
#include <fmt/format.h>

#include "app/commands.hpp"
#include "fit/constants_io.hpp"

namespace sglab::app {

void add_constants_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "constants", "List the constant sets, or regenerate the runtime header from them");
  auto dir = std::make_shared<std::string>();
  auto header = std::make_shared<std::string>();
  auto write = std::make_shared<bool>(false);
  add_path_option(cmd, "--dir", *dir,
                  "directory of constant-set JSON files (default: data/constants of the sglab "
                  "project found at or above the working directory)");
  add_path_option(cmd, "--header", *header,
                  "header to write with --write-header (default: include/sglab/constants.hpp of "
                  "the project when --dir is its data/constants, else DIR/constants.hpp)");
  cmd->add_flag("--write-header", *write,
                "regenerate the header from the JSON files (all or nothing: every set the code "
                "uses must be present and valid)");
  cmd->callback([dir, header, write] {
    try {
      const std::filesystem::path folder =
          dir->empty() ? fit::default_constants_dir() : std::filesystem::path(*dir);
      if (*write) {
        const std::filesystem::path out =
            header->empty() ? fit::default_header_for(folder) : std::filesystem::path(*header);
        const std::size_t n = fit::write_constants_header(folder, out);
        fmt::print("wrote {} ({} constant sets)\n", out.string(), n);
        return;
      }
      if (!header->empty()) throw InputError("--header applies only with --write-header");
      for (const auto& set : fit::load_constant_sets(folder)) {
        const auto& prov = set["provenance"];
        const std::string objective =
            prov.contains("objective") ? prov["objective"].get<std::string>() : "?";
        fmt::print("{:<32} {:<14} {}\n", set["cpp_name"].get<std::string>(),
                   fit::comment_text(objective),
                   fit::comment_text(set["coefficients"].dump(
                       -1, ' ', false, fit::ordered_json::error_handler_t::replace)));
      }
    } catch (const fit::ConstantsError& e) {
      throw InputError(e.what());
    }
  });
}

}  // namespace sglab::app
