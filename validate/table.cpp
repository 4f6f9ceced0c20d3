#include "validate/table.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "common/io.hpp"

namespace sglab::validate {

Table::Table(std::string title, std::vector<Column> columns)
    : title_(std::move(title)), columns_(std::move(columns)) {}

std::size_t Table::column_index(std::string_view name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i].name == name) return i;
  throw std::out_of_range(fmt::format("table '{}' has no column '{}'", title_, name));
}

void Table::add_row(std::vector<Cell> row) {
  if (row.size() != columns_.size())
    throw std::invalid_argument(fmt::format("table '{}': row has {} cells, expected {}", title_,
                                            row.size(), columns_.size()));
  rows_.push_back(std::move(row));
}

namespace {

std::string nonfinite_text(double x) {
  if (std::isnan(x)) return "nan";
  return x > 0 ? "inf" : "-inf";
}

// Shortest text that reads back to the same double.
std::string full_precision(double x) {
  if (!std::isfinite(x)) return nonfinite_text(x);
  return fmt::format("{}", x);
}

std::string cell_text(const Cell& cell, int digits, bool full) {
  struct Visitor {
    int digits;
    bool full;
    std::string operator()(std::monostate) const { return {}; }
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(double x) const {
      if (full || !std::isfinite(x)) return full_precision(x);
      return fmt::format("{:.{}g}", x, digits < 1 ? 1 : digits);
    }
    std::string operator()(std::int64_t n) const { return fmt::format("{}", n); }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
  };
  return std::visit(Visitor{digits, full}, cell);
}

std::string csv_field(std::string s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  out += '"';
  return out;
}

std::string markdown_field(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char ch : s) {
    if (ch == '|')
      out += "\\|";
    else if (ch == '\n' || ch == '\r')
      out += ' ';
    else
      out += ch;
  }
  return out;
}

bool is_numeric(const Cell& cell) {
  return std::holds_alternative<double>(cell) || std::holds_alternative<std::int64_t>(cell);
}

nlohmann::ordered_json cell_json(const Cell& cell) {
  struct Visitor {
    nlohmann::ordered_json operator()(std::monostate) const { return nullptr; }
    nlohmann::ordered_json operator()(const std::string& s) const { return s; }
    nlohmann::ordered_json operator()(double x) const {
      if (!std::isfinite(x)) return nullptr;
      return x;
    }
    nlohmann::ordered_json operator()(std::int64_t n) const { return n; }
    nlohmann::ordered_json operator()(bool b) const { return b; }
  };
  return std::visit(Visitor{}, cell);
}

}  // namespace

std::string to_csv(const Table& table) {
  std::string out;
  const auto& cols = table.columns();
  for (std::size_t i = 0; i < cols.size(); ++i) {
    if (i) out += ',';
    out += csv_field(cols[i].name);
  }
  out += '\n';
  for (const auto& row : table.rows()) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) out += ',';
      out += csv_field(cell_text(row[i], 0, true));
    }
    out += '\n';
  }
  return out;
}

std::string to_markdown(const Table& table) {
  const auto& cols = table.columns();
  // A column is right-aligned when every non-empty cell in it is a number.
  std::vector<bool> numeric(cols.size(), true);
  for (const auto& row : table.rows())
    for (std::size_t i = 0; i < row.size(); ++i)
      if (!std::holds_alternative<std::monostate>(row[i]) && !is_numeric(row[i]))
        numeric[i] = false;

  std::string out;
  if (!table.title().empty()) out += fmt::format("**{}**\n\n", markdown_field(table.title()));
  out += '|';
  for (const Column& c : cols) out += fmt::format(" {} |", markdown_field(c.name));
  out += "\n|";
  for (std::size_t i = 0; i < cols.size(); ++i) out += numeric[i] ? "---:|" : ":---|";
  out += '\n';
  for (const auto& row : table.rows()) {
    out += '|';
    for (std::size_t i = 0; i < row.size(); ++i)
      out += fmt::format(" {} |", markdown_field(cell_text(row[i], cols[i].digits, false)));
    out += '\n';
  }
  return out;
}

nlohmann::ordered_json to_json_records(const Table& table) {
  nlohmann::ordered_json records = nlohmann::ordered_json::array();
  const auto& cols = table.columns();
  for (const auto& row : table.rows()) {
    nlohmann::ordered_json obj = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < row.size(); ++i) obj[cols[i].name] = cell_json(row[i]);
    records.push_back(std::move(obj));
  }
  return records;
}

nlohmann::ordered_json to_json(const Table& table) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  j["title"] = table.title();
  nlohmann::ordered_json cols = nlohmann::ordered_json::array();
  for (const Column& c : table.columns()) cols.push_back(c.name);
  j["columns"] = std::move(cols);
  j["rows"] = to_json_records(table);
  return j;
}

std::string render(const Table& table, TableFormat format) {
  switch (format) {
    case TableFormat::csv:
      return to_csv(table);
    case TableFormat::markdown:
      return to_markdown(table);
    case TableFormat::json:
      return to_json(table).dump(2) + "\n";
  }
  throw std::logic_error("unknown table format");
}

std::vector<std::filesystem::path> write_table(const Table& table, const std::filesystem::path& dir,
                                               std::string_view stem,
                                               std::initializer_list<TableFormat> formats) {
  std::vector<std::filesystem::path> paths;
  for (TableFormat f : formats) {
    auto path = dir / fmt::format("{}.{}", stem, io::to_string(f));
    io::write_file_atomic(path, render(table, f));
    paths.push_back(std::move(path));
  }
  return paths;
}

}  // namespace sglab::validate
