// cost/cost_table.cpp — see cost_table.hpp.
#include "cost/cost_table.hpp"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <system_error>
#include <thread>

#include <fmt/format.h>

#include "common/io.hpp"
#include "common/json_input.hpp"

#ifndef SGLAB_BUILD_TYPE
#define SGLAB_BUILD_TYPE "unknown"
#endif

namespace sglab::embedded {
std::string_view cost_table_json();  // builtin_cost_table.cpp, generated (cost/CMakeLists.txt)
}  // namespace sglab::embedded

namespace sglab::cost {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

const Cost* CostTable::find(CostKind kind, std::string_view method, io::Precision precision,
                            CostMode mode) const {
  for (const Cost& c : costs)
    if (c.kind == kind && c.method == method && c.precision == precision && c.mode == mode)
      return &c;
  return nullptr;
}

double load_average_1min() {
  std::ifstream in("/proc/loadavg");
  double x = -1;
  if (!(in >> x)) return -1;
  return x;
}

CostTableInfo current_cost_table_info() {
  CostTableInfo info;
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  info.date = buffer;
  info.cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string v = line.substr(colon + 1);
    const auto first = v.find_first_not_of(" \t");
    info.cpu = first == std::string::npos ? std::string("unknown") : v.substr(first);
    break;
  }
  info.cores = std::thread::hardware_concurrency();
#if defined(__clang__)
  info.compiler_id = "Clang";
  info.compiler_version =
      fmt::format("{}.{}.{}", __clang_major__, __clang_minor__, __clang_patchlevel__);
#elif defined(__GNUC__)
  info.compiler_id = "GNU";
  info.compiler_version = fmt::format("{}.{}.{}", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
#else
  info.compiler_id = "unknown";
  info.compiler_version = "unknown";
#endif
  info.build_type = SGLAB_BUILD_TYPE;
  return info;
}

json to_json(const CostTable& t) {
  json doc;
  doc["format"] = "sglab-costs";
  doc["version"] = 1;
  doc["date"] = t.info.date;
  doc["command"] = t.info.command;
  json load = json::array();
  load.push_back(t.info.load_start);
  load.push_back(t.info.load_end);
  doc["machine"] = {{"cpu", t.info.cpu}, {"cores", t.info.cores}, {"load_average_1min", load}};
  doc["compiler"] = {{"id", t.info.compiler_id}, {"version", t.info.compiler_version}};
  doc["build_type"] = t.info.build_type;
  doc["timer"] = t.info.timer;
  doc["inputs"] = t.info.inputs;
  json rows = json::array();
  for (const Cost& c : t.costs)
    rows.push_back({{"kind", std::string(to_string(c.kind))},
                    {"method", c.method},
                    {"precision", std::string(to_string(c.precision))},
                    {"mode", std::string(to_string(c.mode))},
                    {"ns_per_eval", c.ns_per_eval}});
  doc["costs"] = std::move(rows);
  if (t.gpu) doc["gpu"] = gpu::to_json(*t.gpu);
  return doc;
}

void write_cost_table(const CostTable& table, const fs::path& path) {
  io::write_file_atomic(path, to_json(table).dump(2) + "\n");
}

namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw CostTableError(fmt::format("cost table {}: {}", path.string(), what));
}

std::string text_field(const fs::path& path, const json& obj, const char* key,
                       const std::string& where) {
  if (!obj.contains(key) || !obj.at(key).is_string())
    fail(path, fmt::format("{}\"{}\" must be a string", where, key));
  return obj.at(key).get<std::string>();
}

}  // namespace

namespace {

// The table `doc` read from `path` (named in messages), validated; its GPU
// section read or skipped as `gpu` says.
CostTable cost_table_from_json(const json& doc, const fs::path& path, GpuSection gpu) {
  if (!doc.is_object()) fail(path, "expected a JSON object");
  if (!doc.contains("format") || doc.at("format") != "sglab-costs")
    fail(path, "\"format\" must be \"sglab-costs\"");
  if (!doc.contains("version") || !doc.at("version").is_number_integer() ||
      doc.at("version").get<long long>() != 1)
    fail(path, "\"version\" must be 1");
  CostTable t;
  t.path = path;
  t.info.date = text_field(path, doc, "date", "");
  t.info.command = text_field(path, doc, "command", "");
  t.info.build_type = text_field(path, doc, "build_type", "");
  t.info.timer = text_field(path, doc, "timer", "");
  t.info.inputs = text_field(path, doc, "inputs", "");
  if (!doc.contains("machine") || !doc.at("machine").is_object())
    fail(path, "\"machine\" must be an object");
  const json& machine = doc.at("machine");
  t.info.cpu = text_field(path, machine, "cpu", "machine.");
  if (!machine.contains("cores") || !machine.at("cores").is_number_unsigned())
    fail(path, "machine.\"cores\" must be a non-negative integer");
  t.info.cores = machine.at("cores").get<unsigned>();
  if (machine.contains("load_average_1min")) {
    const json& load = machine.at("load_average_1min");
    if (!load.is_array() || load.size() != 2 || !load[0].is_number() || !load[1].is_number())
      fail(path, "machine.\"load_average_1min\" must be [start, end]");
    t.info.load_start = load[0].get<double>();
    t.info.load_end = load[1].get<double>();
  }
  if (!doc.contains("compiler") || !doc.at("compiler").is_object())
    fail(path, "\"compiler\" must be an object");
  t.info.compiler_id = text_field(path, doc.at("compiler"), "id", "compiler.");
  t.info.compiler_version = text_field(path, doc.at("compiler"), "version", "compiler.");
  if (!doc.contains("costs") || !doc.at("costs").is_array())
    fail(path, "\"costs\" must be an array");
  std::size_t i = 0;
  for (const json& row : doc.at("costs")) {
    const std::string where = fmt::format("costs[{}].", i++);
    if (!row.is_object()) fail(path, fmt::format("costs[{}] must be an object", i - 1));
    Cost c;
    const std::string kind = text_field(path, row, "kind", where);
    const std::string precision = text_field(path, row, "precision", where);
    const std::string mode = text_field(path, row, "mode", where);
    c.method = text_field(path, row, "method", where);
    if (c.method.empty()) fail(path, where + "\"method\" is empty");
    const auto k = io::parse_enum<CostKind>(kind);
    if (!k)
      fail(path,
           fmt::format("{}\"kind\": unknown kind '{}' ({})", where, kind, io::one_of<CostKind>()));
    c.kind = *k;
    const auto p = io::parse_enum<io::Precision>(precision);
    if (!p || *p == io::Precision::float16)
      fail(path,
           fmt::format("{}\"precision\": expected float or double, got '{}'", where, precision));
    c.precision = *p;
    const auto m = io::parse_enum<CostMode>(mode);
    if (!m)
      fail(path,
           fmt::format("{}\"mode\": unknown mode '{}' ({})", where, mode, io::one_of<CostMode>()));
    c.mode = *m;
    if (!row.contains("ns_per_eval") || !row.at("ns_per_eval").is_number())
      fail(path, where + "\"ns_per_eval\" must be a number");
    c.ns_per_eval = row.at("ns_per_eval").get<double>();
    if (!std::isfinite(c.ns_per_eval) || !(c.ns_per_eval > 0))
      fail(path,
           fmt::format("{}\"ns_per_eval\" must be finite and > 0, got {}", where, c.ns_per_eval));
    if (t.find(c.kind, c.method, c.precision, c.mode))
      fail(path, fmt::format("{} duplicates {}/{}/{}/{}", where.substr(0, where.size() - 1), kind,
                             c.method, precision, mode));
    t.costs.push_back(std::move(c));
  }
  if (gpu == GpuSection::read && doc.contains("gpu")) {
    try {
      t.gpu = gpu::report_from_json(doc.at("gpu"), "gpu");
    } catch (const std::runtime_error& e) {
      fail(path, e.what());
    }
  }
  return t;
}

}  // namespace

CostTable read_cost_table(const fs::path& path, GpuSection gpu) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    fail(path, "no such file (run `sglab bench --out DIR` to write DIR/costs.json)");
  json doc;
  try {
    doc = io::read_json_file(path, kMaxCostTableBytes, "a cost table");
  } catch (const io::InputError& e) {
    throw CostTableError(fmt::format("cost table {}", e.what()));
  }
  return cost_table_from_json(doc, path, gpu);
}

CostTable builtin_cost_table() {
  const fs::path name(kBuiltinCostTableName);
  json doc;
  try {
    doc = io::parse_json_strict(embedded::cost_table_json(), name.string());
  } catch (const io::InputError& e) {
    throw CostTableError(fmt::format("cost table {}", e.what()));
  }
  return cost_table_from_json(doc, name, GpuSection::read);
}

std::optional<CostTable> read_existing_cost_table(const fs::path& path, GpuSection gpu) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  return read_cost_table(path, gpu);
}

std::optional<fs::path> default_cost_table_path() {
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (ec) return std::nullopt;
  const auto root = io::find_project_root(cwd);
  if (!root) return std::nullopt;
  return *root / "data" / "results" / "costs.json";
}

}  // namespace sglab::cost
