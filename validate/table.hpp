// validate/table.hpp — the one table writer every command uses.
//
// A Table is a title, named columns and rows of cells; it renders as CSV
// (RFC 4180, numbers at full round-trip precision), Markdown (GitHub pipe
// table, numbers to each column's significant digits) and JSON (numbers at
// full precision; NaN and ±inf, which JSON cannot represent, become null in
// JSON and "nan"/"inf"/"-inf" in CSV and Markdown). Files are written with
// io::write_file_atomic.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/vocabulary.hpp"

namespace sglab::validate {

// Empty, text, real, integer or boolean.
using Cell = std::variant<std::monostate, std::string, double, std::int64_t, bool>;

struct Column {
  std::string name;         // CSV header, Markdown header, JSON key
  int digits = 4;           // significant digits of reals in Markdown
  std::string description;  // free text for documentation (not rendered)

  Column(std::string name_, int digits_ = 4, std::string description_ = {})
      : name(std::move(name_)), digits(digits_), description(std::move(description_)) {}
  Column(const char* name_, int digits_ = 4) : Column(std::string(name_), digits_) {}
};

class Table {
 public:
  Table() = default;
  Table(std::string title, std::vector<Column> columns);

  const std::string& title() const { return title_; }
  const std::vector<Column>& columns() const { return columns_; }
  const std::vector<std::vector<Cell>>& rows() const { return rows_; }
  std::size_t column_index(std::string_view name) const;  // throws std::out_of_range

  // Appends a row; throws std::invalid_argument unless it has one cell per column.
  void add_row(std::vector<Cell> row);

  // Cell helpers that keep call sites short.
  static Cell text(std::string_view s) { return Cell{std::string(s)}; }
  static Cell real(double x) { return Cell{x}; }
  static Cell integer(std::int64_t n) { return Cell{n}; }
  static Cell count(std::size_t n) { return Cell{static_cast<std::int64_t>(n)}; }

 private:
  std::string title_;
  std::vector<Column> columns_;
  std::vector<std::vector<Cell>> rows_;
};

// A table's file format, named by its file extension: "csv", "md", "json".
enum class TableFormat { csv, markdown, json };
constexpr std::array<io::EnumName<TableFormat>, 3> names_of(TableFormat) {
  return {{{TableFormat::csv, "csv"}, {TableFormat::markdown, "md"}, {TableFormat::json, "json"}}};
}

// CSV: a header line with the column names, then one line per row; no title.
std::string to_csv(const Table& table);

// Markdown: "**title**", a blank line, then a pipe table (numbers
// right-aligned, '|' in text escaped).
std::string to_markdown(const Table& table);

// [{"column": value, ...}, ...] — one object per row, keys in column order.
nlohmann::ordered_json to_json_records(const Table& table);

// {"title": ..., "columns": [...], "rows": to_json_records(table)}.
nlohmann::ordered_json to_json(const Table& table);

std::string render(const Table& table, TableFormat format);

// Writes `dir/stem.<ext>` for each format atomically; returns the paths.
std::vector<std::filesystem::path> write_table(const Table& table, const std::filesystem::path& dir,
                                               std::string_view stem,
                                               std::initializer_list<TableFormat> formats);

}  // namespace sglab::validate
