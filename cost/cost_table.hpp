// cost/cost_table.hpp — the cost table: what `sglab bench` measured, with
// where and how, so that `sglab pareto` and `sglab recommend` answer the same
// for the same inputs (they read it instead of timing on each call).
//
// JSON, one object:
//   {"format": "sglab-costs", "version": 1,
//    "date": "2026-12-01T05:40:00Z",              // UTC, when bench ran
//    "command": "sglab bench --out data/results",
//    "machine": {"cpu": "<model name of /proc/cpuinfo>", "cores": 2,
//                "load_average_1min": [start, end]},
//    "compiler": {"id": "GNU", "version": "12.2.0"}, "build_type": "Release",
//    "timer": "...", "inputs": "<cost_input_description()>",
//    "costs": [{"kind": "irradiance", "method": "hill", "precision": "float",
//               "mode": "batch", "ns_per_eval": 4.2}, ...]}
// kind ∈ {irradiance, hemispherical, erf}, precision ∈ {float, double},
// mode ∈ {scalar, batch, light_setup, light_eval}; ns_per_eval finite and > 0.
// Optionally "gpu": what `sglab gpucost --out DIR` measured with AMD's shader
// compiler (cost/gpu_report.hpp, gpu::to_json): driver, command and a row
// per (method, family, lang). `sglab bench` keeps it, `sglab gpucost` keeps the
// rest. The committed table is data/results/costs.json.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io.hpp"
#include "cost/cpu_timing.hpp"
#include "cost/gpu_report.hpp"

namespace sglab::cost {

// A missing, unreadable or malformed cost table; the message names the file
// (and the key or entry that is wrong). Bad input: `sglab` exits with 2.
struct CostTableError : io::InputError {
  using io::InputError::InputError;
};

struct CostTableInfo {
  std::string date;                       // ISO 8601 UTC
  std::string command;                    // how it was produced
  std::string cpu;                        // model name from /proc/cpuinfo ("unknown" when absent)
  unsigned cores = 0;                     // std::thread::hardware_concurrency
  double load_start = -1, load_end = -1;  // 1-minute load average (/proc/loadavg), −1 when unknown
  std::string compiler_id, compiler_version, build_type;
  std::string timer;
  std::string inputs;
};

struct CostTable {
  std::filesystem::path path;  // where it was read from (empty when built in memory)
  CostTableInfo info;
  std::vector<Cost> costs;
  std::optional<gpu::Report> gpu;
  // The row for (kind, method, precision, mode), or nullptr.
  const Cost* find(CostKind kind, std::string_view method, io::Precision precision,
                   CostMode mode) const;
};

// This machine, compiler and build (date = now); command, timer and inputs
// left for the caller.
CostTableInfo current_cost_table_info();
double load_average_1min();  // −1 when /proc/loadavg is unreadable

nlohmann::ordered_json to_json(const CostTable& table);
// Writes the table atomically (temporary + rename).
void write_cost_table(const CostTable& table, const std::filesystem::path& path);
// The largest cost table read (io::read_json_file); one written by `sglab bench` is about 20 KB.
inline constexpr std::size_t kMaxCostTableBytes = 1 << 20;
// Which parts of a table a reader takes: all of it, or all but the "gpu"
// section (left unread and unchecked: for `sglab gpucost --out`, which
// replaces it).
enum class GpuSection { read, skip };
// Reads and validates; throws CostTableError naming `path` and what is wrong.
CostTable read_cost_table(const std::filesystem::path& path, GpuSection gpu = GpuSection::read);
// The table at `path` when it exists (validated), for a writer that replaces
// one part of it; nullopt when there is no file.
std::optional<CostTable> read_existing_cost_table(const std::filesystem::path& path,
                                                  GpuSection gpu = GpuSection::read);

// data/results/costs.json of the project that holds the working directory
// (the first folder upwards with data/results and include/sglab), or nullopt.
std::optional<std::filesystem::path> default_cost_table_path();

// The committed cost table compiled into sglab: data/results/costs.json of the
// source it was built from, as it was at build time. Commands that read costs
// fall back to it outside a checkout and name it (kBuiltinCostTableName); its
// `path` is that name.
CostTable builtin_cost_table();
inline constexpr std::string_view kBuiltinCostTableName =
    "compiled into sglab (the data/results/costs.json it was built with)";

}  // namespace sglab::cost
