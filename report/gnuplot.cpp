#include "report/gnuplot.hpp"

#include <cmath>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "common/atomic_files.hpp"
#include "common/io.hpp"

namespace sglab::report {

namespace fs = std::filesystem;

namespace figures_detail {

// gnuplot single-quoted string: only ' needs doubling.
std::string gp_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

// A CSV from a header and rows of numbers (full precision; NaN → "nan").
// `block` > 0 inserts a blank line every `block` rows (gnuplot scan lines).
std::string numeric_csv(const std::vector<std::string>& header,
                        const std::vector<std::vector<double>>& rows, std::size_t block) {
  std::string s;
  for (std::size_t i = 0; i < header.size(); ++i) s += (i ? "," : "") + header[i];
  s += '\n';
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (block && r && r % block == 0) s += '\n';
    for (std::size_t i = 0; i < rows[r].size(); ++i) {
      const double x = rows[r][i];
      s += i ? "," : "";
      s += std::isfinite(x) ? fmt::format("{}", x)
                            : (std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf"));
    }
    s += '\n';
  }
  return s;
}

// Writes <stem>.gp next to the data and runs gnuplot in `dir`; the body is
// rendered once to PNG and once to SVG. Returns the script, PNG and SVG paths.
std::vector<fs::path> render(const FiguresOptions& opt, const std::string& stem,
                             const std::string& body, int width, int height) {
  const fs::path& dir = opt.out;
  auto block = [&](const std::string& terminal, const std::string& ext) {
    return fmt::format(
        "reset\n"
        "set encoding utf8\n"
        "set datafile separator ','\n"
        "set key autotitle columnhead\n"
        "set terminal {} size {},{} noenhanced font 'DejaVu Sans,11' background rgb 'white'\n"
        "set output {}\n"
        "{}\n"
        "unset multiplot\n"
        "set output\n",
        terminal, width, height, gp_quote(stem + "." + ext), body);
  };
  const std::string script =
      fmt::format("# gnuplot script written by `sglab figures`; run in this directory.\n{}\n{}",
                  block("pngcairo", "png"), block("svg", "svg"));
  const fs::path gp = dir / (stem + ".gp");
  const fs::path log = dir / (stem + ".gp.log");
  // gnuplot opens its outputs itself: refuse first what is not a regular file there.
  for (const fs::path& p : {log, dir / (stem + ".png"), dir / (stem + ".svg")})
    io::check_output_path(p);
  io::write_file_atomic(gp, script);
  // No shell: gnuplot runs in `dir` with an argument vector.
  const int status = io::run_program({opt.gnuplot, stem + ".gp"}, dir, stem + ".gp.log");
  if (status != 0) {
    std::string tail;
    try {
      tail = io::read_file(log);
      if (tail.size() > 2000) tail = tail.substr(tail.size() - 2000);
    } catch (...) {
    }
    throw std::runtime_error(fmt::format("gnuplot failed on {} (exit status {}); log {}:\n{}",
                                         gp.string(), status, log.string(), tail));
  }
  {
    std::error_code ec;
    if (fs::file_size(log, ec) == 0 && !ec)
      fs::remove(log, ec);  // keep the log only when gnuplot said something
  }
  for (const char* ext : {"png", "svg"}) {
    const fs::path p = dir / (stem + "." + ext);
    std::error_code ec;
    if (!fs::exists(p, ec) || fs::file_size(p, ec) == 0)
      throw std::runtime_error(fmt::format("gnuplot ran {} but {} is missing or empty (log {})",
                                           gp.string(), p.string(), log.string()));
  }
  return {stem + ".gp", stem + ".png", stem + ".svg"};
}

}  // namespace figures_detail

bool gnuplot_available(const std::string& gnuplot) {
  return !gnuplot.empty() && io::run_program({gnuplot, "--version"}) == 0;
}

}  // namespace sglab::report
