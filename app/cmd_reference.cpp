// `sglab reference --points FILE [--precision standard|high]`: the reference
// engine (reference/reference.hpp) on the points of a CSV file.
// `sglab reference --check-table [--oversample K]`: the irradiance table
// (reference/irradiance_table.hpp) against the quadrature on the grid K times
// finer than its nodes (check_irradiance_table), per piece; exit 1 when any
// point is beyond its bound.
//
// Input: a header line `kappa,cosine`, then one `κ,c` per line (finite
// κ ≥ 0, c ∈ [−1, 1]); CRLF line ends and blanks around fields are accepted,
// empty lines are skipped. Output (stdout): CSV with the header
// `kappa,cosine,hemispherical,irradiance,normalized`, every value printed
// with 17 significant digits (%.17g), so doubles round-trip exactly.
// The file is read once: each row is checked before it is evaluated and
// printed, so a bad line is an InputError (exit 2) naming the file and the
// line number after the rows before it were printed. A UTF-8 byte-order
// mark before the header is skipped. Rows are streamed (memory does not grow
// with the file); progress on stderr when it is a terminal.
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "app/points.hpp"
#include "common/args.hpp"
#include "common/io.hpp"
#include "reference/irradiance_table.hpp"
#include "reference/reference.hpp"

namespace sglab::app {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// Splits a line at commas (no quoting: the fields are numbers).
std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

// The dense check of the irradiance table, one line per piece, then the whole.
void check_table(int oversample) {
  const auto t0 = std::chrono::steady_clock::now();
  const reference::IrradianceTable& table = reference::irradiance_table();
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t nodes = 0;
  for (const auto& p : table.pieces()) nodes += p.coefficients.size();
  fmt::print(
      "irradiance table: {} pieces, {} nodes, built in {:.2f} s; checked against the quadrature "
      "at the angles πj/(kn), k = {}, of each piece's n nodes per direction (between the nodes, "
      "none of them a node, and on the piece edges), both signs of c\n\n",
      table.pieces().size(), nodes, build, oversample);
  fmt::print("  {:<22} {:>7} {:>9} {:>13}  {}\n", "piece (κ)", "nodes", "points", "max error",
             "worst (κ, c)");
  const auto points = reference::irradiance_table_check_points(oversample);
  reference::IrradianceTableCheck all;
  for (const auto& p : table.pieces()) {
    std::vector<reference::Query> mine;
    for (const auto& q : points)
      if (&table.piece_of(q.kappa) == &p) mine.push_back(q);
    const auto r = reference::check_irradiance_table(mine, true);
    const char* axis = p.axis == reference::IrradianceTable::Axis::linear
                           ? "κ"
                           : (p.axis == reference::IrradianceTable::Axis::log ? "ln κ" : "1/κ");
    fmt::print("  {:<22} {:>7} {:>9} {:>13.3g}  ({:.6g}, {:.6g})\n",
               fmt::format("[{:g}, {:g}] in {}", p.kappa_lo, p.kappa_hi, axis),
               fmt::format("{}x{}", p.kappa_nodes, p.cosine_nodes), r.points, r.max_error,
               r.worst_kappa, r.worst_cosine);
    all.points += r.points;
    if (!(r.max_error <= all.max_error))
      all = {all.points, r.max_error, r.worst_kappa, r.worst_cosine};
  }
  fmt::print(
      "\n  all: {} points, max |E_table − E| / E(1, κ) = {:.3g} at κ = {:.17g}, c = {:.17g} "
      "(bound {:g})\n",
      all.points, all.max_error, all.worst_kappa, all.worst_cosine,
      reference::kIrradianceTableBound);
  std::fflush(stdout);
  if (!(all.max_error <= reference::kIrradianceTableBound))
    throw std::runtime_error(fmt::format("the irradiance table exceeds its bound {:g}: {:.3g}",
                                         reference::kIrradianceTableBound, all.max_error));
}

}  // namespace

std::size_t for_each_point(const std::string& path,
                           const std::function<void(const reference::Query&)>& on_point,
                           std::optional<io::NumberFormat> kappa_format) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format("{}: no such points file (or not a regular file)", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open points file", path));

  std::size_t count = 0;
  // one byte more than a line may have, and the NUL
  std::vector<char> buffer(kMaxPointsLineBytes + 2);
  std::size_t line_number = 0;
  bool header_seen = false;
  while (true) {
    // Bounded: istream::getline stores at most buffer.size() - 1 bytes.
    in.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.bad()) throw InputError(fmt::format("{}: read error", path));
    const bool ended_by_newline = !in.eof() && !in.fail();
    const auto extracted = static_cast<std::size_t>(in.gcount());
    if (extracted == 0 && in.eof()) break;
    ++line_number;
    std::string_view text(buffer.data(), extracted - (ended_by_newline ? 1 : 0));
    auto fail = [&](std::string_view why) {
      return InputError(
          fmt::format("{}:{}: {} (line: {})", path, line_number, why, io::quote_escaped(text)));
    };
    if (text.size() > kMaxPointsLineBytes)
      throw fail(fmt::format("line longer than {} bytes", kMaxPointsLineBytes));
    if (line_number == 1) text = io::strip_utf8_bom(text);  // a byte-order mark some editors write
    text = trim(text);
    if (text.empty()) continue;
    const auto fields = split(text);
    if (!header_seen) {
      if (fields.size() != 2 || fields[0] != "kappa" || fields[1] != "cosine")
        throw fail("expected the header \"kappa,cosine\"");
      header_seen = true;
      continue;
    }
    if (fields.size() != 2)
      throw fail(fmt::format("expected 2 fields (kappa,cosine), found {}", fields.size()));
    double value[2];
    for (int i = 0; i < 2; ++i) {
      const std::string_view f = fields[i];
      const char* name = i == 0 ? "kappa" : "cosine";
      if (f.empty()) throw fail(fmt::format("missing {}", name));
      const auto [end, err] = std::from_chars(f.data(), f.data() + f.size(), value[i]);
      if (err != std::errc() || end != f.data() + f.size())
        throw fail(fmt::format("{} is not a number: {}", name, io::quote_escaped(f)));
    }
    const double kappa = value[0], cosine = value[1];
    if (const std::string why =
            io::point_error(kappa, cosine, kappa_format ? &*kappa_format : nullptr);
        !why.empty())
      throw fail(why);
    on_point(reference::Query{kappa, cosine});
    ++count;
  }
  if (!header_seen)
    throw InputError(fmt::format("{}: empty file, expected the header \"kappa,cosine\"", path));
  return count;
}

void add_reference_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("reference",
                                 "Reference H(c,κ), E(c,κ), s(c,κ) (docs/quantities.md) by "
                                 "quadrature at the points of a CSV file");
  auto points = std::make_shared<std::string>();
  auto precision = std::make_shared<std::string>("standard");
  auto check = std::make_shared<bool>(false);
  auto oversample = std::make_shared<int>(9);
  add_path_option(cmd, "--points", *points, "CSV file with the header kappa,cosine");
  cmd->add_option("--precision", *precision,
                  "standard (double quadrature) or high (50-digit, slow)")
      ->check(CLI::IsMember({"standard", "high"}))
      ->capture_default_str();
  cmd->add_flag("--check-table", *check,
                "instead: check the irradiance table (the fast E of scenes and envmaps) against "
                "the quadrature between its nodes; exit 1 beyond its bound");
  cmd->add_option("--oversample", *oversample,
                  "--check-table: the grid is this many times finer than the nodes (odd)")
      ->check(count_in(1, 31))
      ->capture_default_str();
  cmd->callback([points, precision, check, oversample] {
    if (points->empty() == !*check)
      throw InputError("give exactly one of --points FILE and --check-table");
    if (*check) {
      if (*oversample % 2 == 0)
        throw InputError(fmt::format(
            "--oversample: must be odd (an even one puts grid points on the nodes), got {}",
            *oversample));
      check_table(*oversample);
      return;
    }
    // One pass: rows are evaluated and printed a chunk at a time, so memory
    // does not grow with the file; a bad row stops the command after the
    // rows before it are printed.
    const auto mode =
        *precision == "high" ? reference::Quadrature::high : reference::Quadrature::standard;
    io::Progress progress("reference", 0);
    constexpr std::size_t kChunk = 4096;  // rows per engine call (each call runs in parallel)
    std::vector<reference::Query> chunk;
    chunk.reserve(kChunk);
    // printed with the first rows
    std::string out = "kappa,cosine,hemispherical,irradiance,normalized\n";
    const auto flush = [&] {
      const auto results = reference::reference_engine().evaluate(chunk, mode);
      for (const auto& r : results)
        out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", r.kappa, r.cosine,
                           r.hemispherical, r.irradiance, r.normalized);
      std::fwrite(out.data(), 1, out.size(), stdout);
      out.clear();
      progress.advance(chunk.size());
      chunk.clear();
      // The engine caches every point it evaluates; a points file is read
      // once, so keep the cache from growing with the file.
      if (reference::reference_engine().cache_size() > 8 * kChunk)
        reference::reference_engine().clear_cache();
    };
    try {
      for_each_point(*points, [&](const reference::Query& q) {
        chunk.push_back(q);
        if (chunk.size() == kChunk) flush();
      });
    } catch (const InputError&) {
      if (!chunk.empty()) flush();  // every row before the bad one is printed
      progress.finish();
      std::fflush(stdout);
      throw;
    }
    flush();  // the last rows, or the header of a file without rows
    progress.finish();
    std::fflush(stdout);
  });
}

}  // namespace sglab::app
