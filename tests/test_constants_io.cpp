// Constants JSON is untrusted input: the schema (fit/constants_schema.hpp)
// matches include/sglab/params.hpp and the code's constants::NAME references;
// every malformed or unsafe file is refused with exit 2 naming the file and
// the key, and nothing is written; text reaches the header only as safe
// comments; sets and header are written all or nothing; the project is found
// from the working directory.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "fit/constants_io.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::fit::ordered_json;
using sglab::test::run_sglab;

using sglab::test::kRoot;
const fs::path kConstants = kRoot / "data" / "constants";

using sglab::test::TempDir;

using sglab::test::WorkingDirectory;

// A copy of the checkout's constant sets in dir/constants.
fs::path copy_constants(const fs::path& dir) {
  const fs::path to = dir / "constants";
  fs::create_directories(to);
  for (const auto& e : fs::directory_iterator(kConstants))
    fs::copy_file(e.path(), to / e.path().filename());
  return to;
}

using sglab::test::write_file;

std::string replace_once(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << "'" << from << "' not in the file";
  if (pos != std::string::npos) s.replace(pos, from.size(), to);
  return s;
}

// ---- the schema -------------------------------------------------------------

std::string squeeze(std::string s) {
  s = std::regex_replace(s, std::regex(R"(\s+)"), " ");
  s = std::regex_replace(s, std::regex(R"(^ | $)"), "");
  return std::regex_replace(s, std::regex(R"( ?\[ ?)"), "[");
}

TEST(Schema, MatchesParamsHpp) {
  // Every `template <class S, std::size_t X...> struct Name { S members; };`
  // of params.hpp, member by member, against the table.
  const std::string text = sglab::io::read_file(kRoot / "include" / "sglab" / "params.hpp");
  const std::regex decl(
      R"(template\s*<\s*class\s+S((?:\s*,\s*std::size_t\s+\w+)*)\s*>\s*struct\s+(\w+)\s*\{([^}]*)\};)");
  std::map<std::string, std::pair<std::vector<std::string>, std::vector<std::string>>> in_header;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), decl); it != std::sregex_iterator();
       ++it) {
    std::vector<std::string> sizes, members;
    const std::string params = (*it)[1];
    const std::regex size_param(R"(std::size_t\s+(\w+))");
    for (auto s = std::sregex_iterator(params.begin(), params.end(), size_param);
         s != std::sregex_iterator(); ++s)
      sizes.push_back((*s)[1]);
    std::string body = std::regex_replace(std::string((*it)[3]), std::regex(R"(//[^\n]*)"), "");
    std::stringstream statements(body);
    for (std::string statement; std::getline(statements, statement, ';');) {
      statement = squeeze(statement);
      if (statement.empty()) continue;
      ASSERT_EQ(statement.rfind("S ", 0), 0u) << (*it)[2] << ": '" << statement << "'";
      std::stringstream names(statement.substr(2));
      for (std::string name; std::getline(names, name, ',');) members.push_back(squeeze(name));
    }
    in_header[(*it)[2]] = {sizes, members};
  }
  ASSERT_GE(in_header.size(), 10u);
  std::set<std::string> in_table;
  for (const auto& p : sglab::fit::param_structs()) {
    in_table.insert(std::string(p.name));
    const auto h = in_header.find(std::string(p.name));
    ASSERT_NE(h, in_header.end()) << p.name << " is in the schema but not in params.hpp";
    EXPECT_EQ(h->second.first, std::vector<std::string>(p.size_params.begin(), p.size_params.end()))
        << p.name;
    std::vector<std::string> members;
    for (auto m : p.members) members.push_back(squeeze(std::string(m)));
    EXPECT_EQ(h->second.second, members) << p.name;
  }
  for (const auto& [name, _] : in_header)
    EXPECT_TRUE(in_table.count(name)) << name << " is missing from the schema";
}

TEST(Schema, ArrayLengthsFollowTheSizeParameters) {
  const auto r = sglab::fit::resolve_cpp_type("SteepnessRationalParams<double,0>", "t");
  EXPECT_EQ(r.canonical, "SteepnessRationalParams<double, 0>");
  EXPECT_EQ(r.members, (std::vector<std::pair<std::string, std::size_t>>{{"p", 1}, {"q", 1}}));
  EXPECT_EQ(
      sglab::fit::resolve_cpp_type("SteepnessRationalParams<double, 3>", "t").members[1].second,
      4u);
  const auto l = sglab::fit::resolve_cpp_type("Listing5Params<double, 6, 7>", "t");
  EXPECT_EQ(l.members, (std::vector<std::pair<std::string, std::size_t>>{
                           {"split", 0}, {"cutoff", 0}, {"small", 6}, {"large", 7}}));
  for (const char* bad :
       {"Listing5Params<double, 6>", "Listing5Params<float, 6, 7>", "Nope<double>",
        "AbramowitzStegunParams<double, 0>", "AbramowitzStegunParams<double, 65>",
        "AbramowitzStegunParams<double, -1>", "HillParams<double>; int x", "HillParams"})
    EXPECT_THROW(sglab::fit::resolve_cpp_type(bad, "t"), sglab::fit::ConstantsError) << bad;
}

TEST(Schema, RequiredSetsCoverEveryReferenceInTheCode) {
  std::set<std::string> required;
  for (const auto& r : sglab::fit::required_sets()) {
    required.insert(std::string(r.cpp_name));
    EXPECT_EQ(sglab::fit::resolve_cpp_type(r.cpp_type, "t").canonical, r.cpp_type)
        << "not canonical: " << r.cpp_type;
  }
  const std::regex ref(R"((?:^|[^:\w])(?:sglab::)?constants::([a-z_][a-z0-9_]*))");
  std::size_t references = 0;
  for (const char* folder : {"include", "validate", "fit", "app", "bench", "tests"}) {
    if (!fs::exists(kRoot / folder)) continue;
    for (const auto& e : fs::recursive_directory_iterator(kRoot / folder)) {
      const auto ext = e.path().extension();
      if (e.path().filename() == "constants.hpp" || (ext != ".hpp" && ext != ".cpp")) continue;
      const std::string text = sglab::io::read_file(e.path());
      for (auto it = std::sregex_iterator(text.begin(), text.end(), ref);
           it != std::sregex_iterator(); ++it) {
        ++references;
        EXPECT_TRUE(required.count((*it)[1]))
            << e.path() << " uses constants::" << (*it)[1]
            << ", which is not in required_sets() (fit/constants_schema.cpp)";
      }
    }
  }
  EXPECT_GT(references, 20u);
}

TEST(Schema, CheckoutSetsAreCompleteAndValid) {
  std::vector<ordered_json> sets;
  std::vector<std::string> files;
  for (auto& f : sglab::fit::load_constant_set_files(kConstants)) {
    files.push_back(f.file.string());
    sets.push_back(std::move(f.set));
  }
  EXPECT_NO_THROW(sglab::fit::validate_header_sets(sets, files));
}

// ---- comments ---------------------------------------------------------------

TEST(CommentText, NothingLeavesTheComment) {
  using sglab::fit::comment_text;
  EXPECT_EQ(comment_text("plain ≈ text, κ ∈ [1e-3, 1e4]"), "plain ≈ text, κ ∈ [1e-3, 1e4]");
  EXPECT_EQ(comment_text("a\nb\r#error x"), "a\\x0ab\\x0d#error x");
  EXPECT_EQ(comment_text(std::string("nul\0here", 8)), "nul\\x00here");
  EXPECT_EQ(comment_text("ends with \\"), "ends with \\x5c");  // never a line splice
  // nor a trigraph splice (C++ before 17)
  EXPECT_EQ(comment_text("ends with ?\?/"), "ends with ?\\x3f/");
  EXPECT_EQ(comment_text("what???"), "what?\\x3f\\x3f");
  EXPECT_EQ(comment_text("\x1b[31m"), "\\x1b[31m");
  EXPECT_EQ(comment_text("bidi \u202e override"), "bidi \\u{202e} override");
  EXPECT_EQ(comment_text("line\u2028sep"), "line\\u{2028}sep");
  EXPECT_EQ(comment_text("c1 \xc2\x85"), "c1 \\u{0085}");
  EXPECT_EQ(comment_text("bad \xff\xc3"), "bad \\xff\\xc3");  // ill-formed UTF-8
  EXPECT_EQ(comment_text("overlong \xc0\xaf"), "overlong \\xc0\\xaf");
  EXPECT_EQ(comment_text("surrogate \xed\xa0\x80"), "surrogate \\xed\\xa0\\x80");
}

// ---- refused files: exit 2, file and key named, nothing written --------------

struct BadFile {
  std::string name;                                        // which test case
  std::string file;                                        // the file of the copy to change
  std::vector<std::pair<std::string, std::string>> edits;  // text replaced in it
  std::string key;          // the key the message must name ("" when none)
  std::string reason;       // a phrase of the message
  bool collection = false;  // wrong only as part of a header (the listing accepts it)
};

TEST(UntrustedConstants, EveryMalformedFileIsRefusedAndNothingWritten) {
  const std::string A = "\"A\": 0.65173288269070562", objective = "\"objective\": \"published\"";
  const std::string hill_type = "\"cpp_type\": \"HillParams<double>\"",
                    hill_name = "\"cpp_name\": \"hill_published\"";
  const std::vector<BadFile> cases = {
      {"unknown coefficient",
       "steepness2022-published.json",
       {{"\"C\":", "\"Z\":"}},
       "coefficients.Z",
       "no member"},
      {"missing coefficient",
       "steepness2022-published.json",
       {{",\n    \"C\": 7.2216687798956709", ""}},
       "coefficients.C",
       "missing"},
      {"array too short",
       "erf-listing5-published.json",
       {{"\"small\": [1.128379121, ", "\"small\": ["}},
       "coefficients.small",
       "needs 6"},
      {"array element not a number",
       "erf-listing5-published.json",
       {{"\"small\": [1.128379121, ", "\"small\": [null, "}},
       "coefficients.small[0]",
       "must be a number"},
      {"overflow",
       "steepness2022-published.json",
       {{A, "\"A\": 1e400"}},
       "coefficients.A",
       "out of range (larger than any double)"},
      {"underflow",
       "steepness2022-published.json",
       {{A, "\"A\": 1e-400"}},
       "coefficients.A",
       "out of range"},
      {"string coefficient",
       "steepness2022-published.json",
       {{A, "\"A\": \"0.6\""}},
       "coefficients.A",
       "must be a number"},
      {"objective not a string",
       "hill-published.json",
       {{objective, "\"objective\": 3"}},
       "provenance.objective",
       "must be a string"},
      {"newline in target",
       "hill-published.json",
       {{"\"target\": \"hill\"", "\"target\": \"hill\\n#error x\""}},
       "target",
       "not a name"},
      {"slash in variant",
       "hill-published.json",
       {{"\"variant\": \"published\"", "\"variant\": \"../x\""}},
       "variant",
       "not a name"},
      {"keyword cpp_name",
       "hill-published.json",
       {{hill_name, "\"cpp_name\": \"int\""}},
       "cpp_name",
       "not a C++ identifier"},
      {"NUL in cpp_name",
       "hill-published.json",
       {{hill_name, "\"cpp_name\": \"hill\\u0000x\""}},
       "cpp_name",
       "'hill\\x00x'"},
      {"injected cpp_type",
       "hill-published.json",
       {{hill_type, "\"cpp_type\": \"HillParams<double> x{}; int y\""}},
       "",
       "cpp_type"},
      {"unknown cpp_type",
       "hill-published.json",
       {{hill_type, "\"cpp_type\": \"HillParam<double>\""}},
       "",
       "unknown parameter struct"},
      {"duplicate key",
       "hill-published.json",
       {{"\"target\": \"hill\",", "\"target\": \"hill\", \"target\": \"x\","}},
       "target",
       "duplicate key"},
      {"ill-formed UTF-8",
       "hill-published.json",
       {{objective, "\"objective\": \"p\xff\""}},
       "",
       "UTF-8"},
      {"provenance not an object",
       "hill-published.json",
       {{"\"provenance\": {", "\"provenance\": 1, \"x\": {"}},
       "provenance",
       "must be an object"},
      {"kappa_range wrong",
       "steepness2022-irradiance.json",
       {{"\"kappa_range\": [", "\"kappa_range\": [\"a\", "}},
       "provenance.kappa_range",
       "two numbers"},
      {"not an object",
       "hill-published.json",
       {{"{\n  \"format\"", "[{\"format\""}, {"\n}", "}]"}},
       "",
       "not a JSON object"},
      {"version wrong",
       "hill-published.json",
       {{"\"version\": 1", "\"version\": 2"}},
       "version",
       "must be 1"},
      {"duplicate cpp_name",
       "steepness2022-optimal-t.json",
       {{"\"cpp_name\": \"steepness2022_optimal_t\"", "\"cpp_name\": \"steepness2022_published\""}},
       "cpp_name",
       "also the cpp_name",
       true},
      {"required set with another type",
       "erf-as7125-published.json",
       {{"AbramowitzStegunParams<double, 3>", "AbramowitzStegunParams<double, 2>"},
        {", 0.7478556]", "]"}},
       "cpp_type",
       "the code uses it as AbramowitzStegunParams<double, 3>",
       true},
  };
  TempDir tmp("constants_bad");
  for (const BadFile& c : cases) {
    SCOPED_TRACE(c.name);
    fs::remove_all(tmp.path / "constants");
    const fs::path dir = copy_constants(tmp.path);
    const fs::path file = dir / c.file;
    std::string text = sglab::io::read_file(file);
    for (const auto& [from, to] : c.edits) text = replace_once(text, from, to);
    write_file(file, text);
    const fs::path header = tmp.path / "out" / "constants.hpp";
    for (bool write_header : {true, false}) {
      if (c.collection && !write_header) continue;
      std::vector<std::string> args = {"constants", "--dir", dir.string()};
      if (write_header) args.insert(args.end(), {"--write-header", "--header", header.string()});
      const auto r = run_sglab(args);
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find(c.file), std::string::npos) << r.output;
      if (!c.key.empty()) {
        EXPECT_NE(r.output.find("key '" + c.key + "'"), std::string::npos) << r.output;
      }
      EXPECT_NE(r.output.find(c.reason), std::string::npos) << r.output;
      EXPECT_FALSE(fs::exists(header)) << "a header was written";
    }
  }
}

// A fit can produce NaN or ±inf, which no file reaches (the parser refuses
// overflow first): the schema refuses each in memory, in a scalar member and
// in an element of an array member, naming the key.
TEST(Schema, NonFiniteCoefficientsAreRefused) {
  const ordered_json good =
      sglab::fit::load_constant_set(kConstants / "erf-listing5-published.json");
  ASSERT_NO_THROW(sglab::fit::validate_constant_set(good, "good"));
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), inf, -inf}) {
    for (const std::string key : {"split", "small[2]", "large[0]"}) {
      SCOPED_TRACE(fmt::format("{} = {}", key, bad));
      ordered_json set = good;
      const auto bracket = key.find('[');
      if (bracket == std::string::npos)
        set["coefficients"][key] = bad;
      else
        set["coefficients"][key.substr(0, bracket)][std::stoul(key.substr(bracket + 1))] = bad;
      try {
        sglab::fit::validate_constant_set(set, "in-memory set");
        ADD_FAILURE() << "accepted";
      } catch (const sglab::fit::ConstantsError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("key 'coefficients." + key + "'"), std::string::npos) << what;
        EXPECT_NE(what.find("must be finite"), std::string::npos) << what;
      }
    }
  }
}

// The fit path: every fit writes through write_sets_and_header, which refuses
// a set with a non-finite coefficient before anything is written — neither
// that set, nor a good set of the same batch, nor the header.
TEST(UntrustedConstants, AFitWithANonFiniteCoefficientWritesNothing) {
  TempDir tmp("constants_nonfinite");
  const fs::path out = tmp.path / "out", header = out / "constants.hpp";
  const ordered_json good =
      sglab::fit::load_constant_set(kConstants / "steepness2024-irradiance.json");
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), inf, -inf}) {
    SCOPED_TRACE(fmt::format("A = {}", bad));
    ordered_json set = good;
    set["coefficients"]["A"] = bad;
    const std::vector<sglab::fit::ConstantSetFile> batch = {
        {out / "hill-published.json",
         sglab::fit::load_constant_set(kConstants / "hill-published.json")},
        {out / "steepness2024-irradiance.json", set}};
    try {
      sglab::fit::write_sets_and_header(batch, out, kConstants, header);
      ADD_FAILURE() << "written";
    } catch (const sglab::fit::ConstantsError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("steepness2024-irradiance.json"), std::string::npos) << what;
      EXPECT_NE(what.find("key 'coefficients.A': must be finite"), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(out / "hill-published.json"));
    EXPECT_FALSE(fs::exists(out / "steepness2024-irradiance.json"));
    EXPECT_FALSE(fs::exists(header));
  }
}

TEST(UntrustedConstants, DeepNestingIsRefusedNotACrash) {
  TempDir tmp("constants_deep");
  const fs::path dir = copy_constants(tmp.path);
  const fs::path file = dir / "hill-published.json";
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  write_file(file, replace_once(sglab::io::read_file(file), "\"objective\": \"published\"",
                                "\"objective\": \"published\", \"x\": " + deep));
  for (bool write_header : {true, false}) {
    std::vector<std::string> args = {"constants", "--dir", dir.string()};
    if (write_header)
      args.insert(args.end(), {"--write-header", "--header", (tmp.path / "h.hpp").string()});
    const auto r = run_sglab(args);
    EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 2000);
    EXPECT_NE(r.output.find("hill-published.json"), std::string::npos) << r.output.substr(0, 2000);
    EXPECT_NE(r.output.find("nested deeper than 64 levels"), std::string::npos)
        << r.output.substr(0, 2000);
    EXPECT_NE(r.output.find("key 'provenance.x"), std::string::npos) << r.output.substr(0, 2000);
  }
  EXPECT_FALSE(fs::exists(tmp.path / "h.hpp"));
  // 64 levels are fine.
  write_file(file, replace_once(sglab::io::read_file(kConstants / "hill-published.json"),
                                "\"objective\": \"published\"",
                                "\"objective\": \"published\", \"x\": " + std::string(62, '[') +
                                    std::string(62, ']')));
  EXPECT_NO_THROW(sglab::fit::load_constant_set(file));
}

TEST(UntrustedConstants, OversizedFileIsRefused) {
  TempDir tmp("constants_big");
  const fs::path dir = copy_constants(tmp.path);
  const fs::path file = dir / "hill-published.json";
  write_file(file, replace_once(sglab::io::read_file(file), "\"objective\": \"published\"",
                                "\"objective\": \"published\", \"x\": \"" +
                                    std::string(2 << 20, 'a') + "\""));
  const auto r = run_sglab({"constants", "--dir", dir.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 1000);
  EXPECT_NE(r.output.find("more than the 1048576 bytes a constants file may have"),
            std::string::npos)
      << r.output.substr(0, 1000);
}

TEST(UntrustedConstants, IncompleteCollectionsWriteNoHeader) {
  TempDir tmp("constants_incomplete");
  fs::create_directories(tmp.path / "empty");
  const fs::path header = tmp.path / "h.hpp";
  auto r = run_sglab({"constants", "--dir", (tmp.path / "empty").string(), "--write-header",
                      "--header", header.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no constant set has cpp_name"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(header));
  const fs::path dir = copy_constants(tmp.path);
  fs::remove(dir / "hill-published.json");
  r = run_sglab(
      {"constants", "--dir", dir.string(), "--write-header", "--header", header.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'hill_published'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(header));
  r = run_sglab({"constants", "--dir", (tmp.path / "missing").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing"), std::string::npos) << r.output;
}

TEST(UntrustedConstants, TextFieldsBecomeSafeComments) {
  TempDir tmp("constants_text");
  const fs::path dir = copy_constants(tmp.path);
  const fs::path file = dir / "hill-published.json";
  std::string text = sglab::io::read_file(file);
  text = replace_once(text, "\"objective\": \"published\"",
                      "\"objective\": \"published\\n#error objective\", \"key\\n#error key\": "
                      "\"v\\u0000\\u001b[2J\\\\\", \"nested\": {\"a\\n#error nested\": "
                      "[\"\\u202e\\n#error\"]}");
  text = replace_once(text, "\"form\": \"", "\"form\": \"\\r\\n#error form\\\\");
  write_file(file, text);
  const fs::path header = tmp.path / "h.hpp";
  const auto r = run_sglab(
      {"constants", "--dir", dir.string(), "--write-header", "--header", header.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string h = sglab::io::read_file(header);
  EXPECT_EQ(h.find('\0'), std::string::npos);
  EXPECT_EQ(h.find('\r'), std::string::npos);
  EXPECT_EQ(h.find('\x1b'), std::string::npos);
  EXPECT_EQ(h.find("\u202e"), std::string::npos);
  std::stringstream lines(h);
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    EXPECT_NE(line.rfind("#error", 0), 0u) << "line " << n << ": " << line;
    if (!line.empty()) {
      EXPECT_NE(line.back(), '\\') << "line " << n << " splices the next: " << line;
    }
  }
  EXPECT_NE(h.find("//   objective: published\\x0a#error objective"), std::string::npos);
  EXPECT_NE(h.find("//   key\\x0a#error key: v\\x00\\x1b[2J\\x5c"), std::string::npos);
  // The listing of the same file escapes too.
  const auto list = run_sglab({"constants", "--dir", dir.string()});
  ASSERT_EQ(list.exit_code, 0) << list.output;
  EXPECT_EQ(list.output.find('\x1b'), std::string::npos);
  EXPECT_NE(list.output.find("published\\x0a#error objective"), std::string::npos) << list.output;
}

// ---- writing -----------------------------------------------------------------

TEST(AtomicFiles, ADestinationThatIsNotARegularFileReplacesNothing) {
  TempDir tmp("atomic");
  const fs::path a = tmp.path / "a.json", b = tmp.path / "b.json",
                 blocked = tmp.path / "header.hpp";
  write_file(a, "old a");
  // refused before any file is written (a rename over it would fail)
  fs::create_directories(blocked);
  try {
    sglab::io::write_files_atomic({{a, "new a"}, {b, "new b"}, {blocked, "header"}});
    FAIL() << "no error";
  } catch (const sglab::io::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(blocked.string() + ": is a directory"), std::string::npos) << m;
  }
  EXPECT_EQ(sglab::io::read_file(a), "old a");
  EXPECT_FALSE(fs::exists(b));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(tmp.path)) ++entries;
  EXPECT_EQ(entries, 2u) << "temporaries left behind";
  // A destination folder that cannot be created: nothing replaced.
  write_file(tmp.path / "file", "x");
  EXPECT_THROW(
      sglab::io::write_files_atomic({{a, "new a"}, {tmp.path / "file" / "sub" / "c", "c"}}),
      std::runtime_error);
  EXPECT_EQ(sglab::io::read_file(a), "old a");
  sglab::io::write_files_atomic({{a, "new a"}, {b, "new b"}});
  EXPECT_EQ(sglab::io::read_file(a), "new a");
  EXPECT_EQ(sglab::io::read_file(b), "new b");
}

// ---- the project is found from the working directory ---------------------------

TEST(Project, FoundFromTheWorkingDirectory) {
  const auto root = sglab::fit::find_project_root(kRoot / "fit");
  ASSERT_TRUE(root);
  EXPECT_TRUE(fs::equivalent(*root, kRoot)) << *root;
  TempDir tmp("project");
  EXPECT_FALSE(sglab::fit::find_project_root(tmp.path));
  // A project elsewhere: the binary reads and writes it, not the tree it was built from.
  const fs::path other = tmp.path / "other";
  fs::create_directories(other / "include" / "sglab");
  fs::create_directories(other / "data");
  fs::copy(kConstants, other / "data" / "constants");
  fs::create_directories(other / "deep" / "er");
  const std::string checkout_header = sglab::io::read_file(sglab::test::kConstantsHeader);
  {
    WorkingDirectory cwd(other / "deep" / "er");
    const auto r = run_sglab({"constants", "--write-header"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find((other / "include" / "sglab" / "constants.hpp").string()),
              std::string::npos)
        << r.output;
  }
  EXPECT_EQ(sglab::io::read_file(other / "include" / "sglab" / "constants.hpp"), checkout_header);
  EXPECT_EQ(sglab::io::read_file(sglab::test::kConstantsHeader), checkout_header);
  // No project: a clear error naming the options, for listing, header and fit.
  WorkingDirectory cwd(tmp.path);
  for (const std::vector<std::string>& args : {std::vector<std::string>{"constants"},
                                               {"constants", "--write-header"},
                                               {"fit", "lambda-d", "--objective", "sphere-ls"}}) {
    const auto r = run_sglab(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("no sglab project found"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--header"), std::string::npos) << r.output;
  }
  // Explicit paths work anywhere; --dir without --header writes DIR/constants.hpp.
  const fs::path copy = copy_constants(tmp.path);
  const auto r = run_sglab({"constants", "--dir", copy.string(), "--write-header"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(sglab::io::read_file(copy / "constants.hpp"), checkout_header);
  // A dry run needs no project.
  const auto d = run_sglab({"fit", "lambda-d", "--objective", "sphere-ls", "--dry-run"});
  EXPECT_EQ(d.exit_code, 0) << d.output;
  EXPECT_NE(d.output.find("dry run: nothing was written"), std::string::npos) << d.output;
}

}  // namespace
