// `sglab eval --method ID --points FILE [--precision float|double] [--quantity Q]`:
// any registered method at the `kappa,cosine` rows of FILE (the reader and
// validation of `sglab reference`, app/points.hpp). Output (stdout): CSV
// `kappa,cosine,value`, κ and c as read (%.17g), the value with %.9g in float
// (evaluated at the float-rounded κ and c) or %.17g in double. The file is
// streamed (memory does not grow with it). An unknown method is an
// InputError (exit 2) before anything is printed; a bad row (also a κ that
// does not survive rounding to float under --precision float) is one after
// the rows before it were printed.
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <fmt/format.h>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "app/points.hpp"

namespace sglab::app {

void add_eval_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("eval", "Evaluate one method at the kappa,cosine rows of a CSV file");
  auto method = std::make_shared<std::string>();
  auto points = std::make_shared<std::string>();
  auto precision = std::make_shared<std::string>("float");
  auto quantity = std::make_shared<std::string>("irradiance");
  cmd->add_option("--method", *method, "method id (see `sglab methods`)")->required();
  add_path_option(cmd, "--points", *points, "CSV file with the header kappa,cosine")->required();
  cmd->add_option("--precision", *precision, "float | double")->capture_default_str();
  cmd->add_option("--quantity", *quantity, "irradiance | hemispherical | normalized")
      ->capture_default_str();
  cmd->callback([method, points, precision, quantity] {
    if (*precision != "float" && *precision != "double")
      throw InputError(fmt::format("--precision must be float or double; got '{}'", *precision));
    std::span<const Method> list;
    if (*quantity == "irradiance")
      list = irradiance_methods;
    else if (*quantity == "hemispherical")
      list = hemispherical_methods;
    else if (*quantity == "normalized")
      list = normalized_methods;
    else
      throw InputError(fmt::format(
          "--quantity must be irradiance, hemispherical or normalized; got '{}'", *quantity));
    const Method* m = find_method(list, *method);
    if (!m) {
      std::string known;
      for (const Method& each : list) known += (known.empty() ? "" : ", ") + std::string(each.id);
      throw InputError(
          fmt::format("unknown {} method '{}' (known: {})", *quantity, *method, known));
    }
    const bool in_float = *precision == "float";
    std::string out = "kappa,cosine,value\n";
    const auto write = [&out] {
      std::fwrite(out.data(), 1, out.size(), stdout);
      out.clear();
    };
    std::size_t rows = 0;
    const auto row = [&](const reference::Query& q) {
      ++rows;
      if (in_float)
        out += fmt::format("{:.17g},{:.17g},{:.9g}\n", q.kappa, q.cosine,
                           m->f32(static_cast<float>(q.cosine), static_cast<float>(q.kappa)));
      else
        out +=
            fmt::format("{:.17g},{:.17g},{:.17g}\n", q.kappa, q.cosine, m->f64(q.cosine, q.kappa));
      if (out.size() >= (1 << 16)) write();
    };
    try {
      for_each_point(*points, row, in_float ? std::optional(io::kFloatFormat) : std::nullopt);
    } catch (const InputError&) {
      if (rows > 0)
        write();  // every row before the bad one (nothing when the file itself is refused)
      std::fflush(stdout);
      throw;
    }
    write();
    std::fflush(stdout);
  });
}

}  // namespace sglab::app
