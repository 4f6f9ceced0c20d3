#include "constants_io.hpp"

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "atomic_files.hpp"
#include "io.hpp"

namespace sglab::fit {

namespace fs = std::filesystem;

std::optional<fs::path> find_project_root(const fs::path& start) { return io::find_project_root(start); }

fs::path project_root() {
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec)
    if (auto root = find_project_root(cwd)) return *root;
  throw ConstantsError(fmt::format(
      "no sglab project found at or above {} (a folder holding both data/constants and include/sglab); run sglab "
      "inside a checkout or name the files with --dir/--out and --header",
      ec ? std::string("the working directory") : cwd.string()));
}

fs::path default_constants_dir() { return project_root() / "data" / "constants"; }
fs::path default_header_path() { return project_root() / "include" / "sglab" / "constants.hpp"; }

namespace {

bool same_folder(const fs::path& a, const fs::path& b) {
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw ConstantsError(
        fmt::format("{}: cannot read: {}", file.string(), std::error_code(errno, std::generic_category()).message()));
  // Read at most one byte past the limit: parse_untrusted_json refuses larger files.
  std::string text(kMaxConstantsFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw ConstantsError(fmt::format("{}: cannot read", file.string()));
  return text;
}

}  // namespace

fs::path default_header_for(const fs::path& dir) {
  const std::optional<fs::path> root = [] {
    std::error_code ec;
    const fs::path cwd = fs::current_path(ec);
    return ec ? std::nullopt : find_project_root(cwd);
  }();
  if (root && same_folder(dir, *root / "data" / "constants")) return *root / "include" / "sglab" / "constants.hpp";
  return dir / "constants.hpp";
}

void check_constant_set(const ordered_json& set, const std::string& where) { validate_constant_set(set, where); }

ordered_json load_constant_set(const fs::path& file) {
  const std::string name = file.string();
  ordered_json set = parse_untrusted_json(read_text(file), name);
  validate_constant_set(set, name);
  return set;
}

namespace {

// The constant set in `file`, or nullopt (and `file` noted in `skipped`, or
// on stderr) when the file is not one by its format tag.
std::optional<ordered_json> load_if_constant_set(const fs::path& file, std::vector<SkippedFile>* skipped) {
  const std::string text = read_text(file);
  if (const auto why = why_not_a_constant_set(text)) {
    if (skipped)
      skipped->push_back({file, *why});
    else
      fmt::print(stderr, "sglab: note: skipped {}: not a constant set: {}\n", file.string(), *why);
    return std::nullopt;
  }
  ordered_json set = parse_untrusted_json(text, file.string());
  validate_constant_set(set, file.string());
  return set;
}

}  // namespace

std::vector<ConstantSetFile> load_constant_set_files(const fs::path& dir, std::vector<SkippedFile>* skipped) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw ConstantsError(fmt::format("{}: not a folder of constant sets{}", dir.string(),
                                     ec ? ": " + ec.message() : std::string()));
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".json") files.push_back(it->path());
  if (ec) throw ConstantsError(fmt::format("cannot list {}: {}", dir.string(), ec.message()));
  std::sort(files.begin(), files.end());
  std::vector<ConstantSetFile> sets;
  for (const auto& file : files)
    if (auto set = load_if_constant_set(file, skipped)) sets.push_back({file, std::move(*set)});
  return sets;
}

std::vector<ordered_json> load_constant_sets(const fs::path& dir) {
  std::vector<ordered_json> sets;
  for (auto& f : load_constant_set_files(dir)) sets.push_back(std::move(f.set));
  return sets;
}

namespace {

// Shortest decimal that round-trips to the same double.
std::string number(const ordered_json& v) {
  std::string s = fmt::format("{}", v.get<double>());
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // reads as a floating literal
  return s;
}

std::string comment_line(const std::string& key, const ordered_json& value) {
  const std::string text =
      value.is_string() ? value.get<std::string>() : value.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
  return fmt::format("//   {}: {}\n", comment_text(key), comment_text(text));
}

}  // namespace

std::string render_constants_header(const std::vector<ordered_json>& sets) {
  std::string out =
      "// sglab/constants.hpp — GENERATED by `sglab constants --write-header` from\n"
      "// data/constants/*.json; do not edit by hand (tests/test_constants.cpp fails\n"
      "// when this file and the JSON disagree). Each set cites its source and, for\n"
      "// refits, the objective, grid and achieved error it was fitted with.\n"
      "#pragma once\n\n#include \"params.hpp\"\n\nnamespace sglab::constants {\n";
  for (const auto& set : sets) {
    const std::string where = set["cpp_name"].get<std::string>();
    const ResolvedType type = resolve_cpp_type(set["cpp_type"].get<std::string>(), where);
    out += fmt::format("\n// {} / {}: {}\n", comment_text(set["target"].get<std::string>()),
                       comment_text(set["variant"].get<std::string>()), comment_text(set["form"].get<std::string>()));
    for (const auto& [key, value] : set["provenance"].items()) out += comment_line(key, value);
    std::string init;
    for (const auto& [name, length] : type.members) {  // declaration order: designated initializers need it
      const ordered_json& value = set["coefficients"].at(name);
      if (!init.empty()) init += ",\n";
      if (length > 0) {
        std::string elems;
        for (const auto& v : value) elems += (elems.empty() ? "" : ", ") + number(v);
        init += fmt::format("    .{} = {{{}}}", name, elems);
      } else {
        init += fmt::format("    .{} = {}", name, number(value));
      }
    }
    out += fmt::format("inline constexpr {} {}{{\n{}}};\n", type.canonical, set["cpp_name"].get<std::string>(), init);
  }
  out += "\n}  // namespace sglab::constants\n";
  return out;
}

namespace {

std::string checked_header(const std::vector<ConstantSetFile>& files) {
  std::vector<ordered_json> sets;
  std::vector<std::string> names;
  for (const auto& f : files) {
    sets.push_back(f.set);
    names.push_back(f.file.string());
  }
  validate_header_sets(sets, names);
  return render_constants_header(sets);
}

}  // namespace

std::size_t write_constants_header(const fs::path& dir, const fs::path& header) {
  const auto files = load_constant_set_files(dir);
  io::write_files_atomic({{header, checked_header(files)}});
  return files.size();
}

std::size_t write_sets_and_header(const std::vector<ConstantSetFile>& new_sets, const fs::path& out_dir,
                                  const std::optional<fs::path>& base_dir, const fs::path& header,
                                  std::vector<SkippedFile>* skipped) {
  // By file name: base, then what out_dir already has, then the new sets.
  std::map<std::string, ConstantSetFile> merged;
  if (base_dir && !same_folder(*base_dir, out_dir))
    for (auto& f : load_constant_set_files(*base_dir, skipped)) merged[f.file.filename().string()] = std::move(f);
  std::error_code ec;
  if (fs::exists(out_dir, ec)) {
    // Files the new sets replace are not loaded: a malformed one may be overwritten.
    std::vector<fs::path> replaced;
    for (const auto& n : new_sets) replaced.push_back(n.file.filename());
    for (fs::directory_iterator it(out_dir, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      if (p.extension() != ".json" || std::find(replaced.begin(), replaced.end(), p.filename()) != replaced.end())
        continue;
      if (auto set = load_if_constant_set(p, skipped)) merged[p.filename().string()] = {p, std::move(*set)};
    }
    if (ec) throw ConstantsError(fmt::format("cannot list {}: {}", out_dir.string(), ec.message()));
  }
  std::vector<io::FileContent> writes;
  for (const auto& n : new_sets) {
    validate_constant_set(n.set, n.file.string());
    merged[n.file.filename().string()] = n;
    writes.push_back({n.file, n.set.dump(2) + "\n"});
  }
  std::vector<ConstantSetFile> all;
  for (auto& [name, f] : merged) all.push_back(std::move(f));
  writes.push_back({header, checked_header(all)});
  io::write_files_atomic(writes);
  return all.size();
}

}  // namespace sglab::fit
