// File input and output (common/io.hpp, common/atomic_files.hpp,
// common/json_input.hpp) and the commands' use of them: an output never
// replaces what is not a regular file, an empty output path is refused, every
// input file is read bounded and only when it is a regular file, and bad JSON
// or CSV input is named (file and key or line) in a short, escaped message.
//
// FIFOs, symbolic links and directories are made in a TempDir; nothing
// outside it is touched.
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/args.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "common/json_input.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::test::run_sglab;
using sglab::test::TempDir;

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A FIFO, a symbolic link to a regular file and a directory in `dir`, each
// named after what it is; the link's target holds "keep".
struct NotRegularFiles {
  fs::path fifo, link, target, folder;
  explicit NotRegularFiles(const fs::path& dir)
      : fifo(dir / "fifo"), link(dir / "link"), target(dir / "target.txt"), folder(dir / "folder") {
    EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    write_text(target, "keep");
    fs::create_symlink(target, link);
    fs::create_directories(folder);
  }
  // Each still is what it was, and the link's target still holds "keep".
  void expect_untouched() const {
    EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
    EXPECT_EQ(read_text(target), "keep");
    EXPECT_TRUE(fs::is_directory(fs::symlink_status(folder)));
  }
};

// ---- outputs -----------------------------------------------------------------

TEST(AtomicWrite, RefusesToReplaceWhatIsNotARegularFile) {
  TempDir dir("io-atomic");
  const NotRegularFiles odd(dir.path);
  const std::pair<fs::path, const char*> cases[] = {
      {odd.fifo, "is a FIFO"}, {odd.link, "is a symbolic link"}, {odd.folder, "is a directory"}};
  for (const auto& [path, type] : cases) {
    try {
      sglab::io::write_file_atomic(path, "new");
      ADD_FAILURE() << "replaced " << path;
    } catch (const sglab::io::InputError& e) {
      EXPECT_TRUE(contains(e.what(), path.string() + ": " + type)) << e.what();
    }
  }
  odd.expect_untouched();
  // Several files as one unit: one bad destination and none is written.
  const fs::path fresh = dir.path / "fresh.txt";
  EXPECT_THROW(sglab::io::write_files_atomic({{fresh, "a"}, {odd.fifo, "b"}}),
               sglab::io::InputError);
  EXPECT_FALSE(fs::exists(fresh));
  odd.expect_untouched();
  // A regular file, or a path below a symbolic link to a folder, is written.
  fs::create_directory_symlink(odd.folder, dir.path / "folder-link");
  sglab::io::write_file_atomic(dir.path / "folder-link" / "x.txt", "x");
  EXPECT_EQ(read_text(odd.folder / "x.txt"), "x");
  sglab::io::write_file_atomic(fresh, "y");
  EXPECT_EQ(read_text(fresh), "y");
}

TEST(AtomicWrite, RefusesAFolderThatIsNotAFolderAndEmptyPaths) {
  TempDir dir("io-atomic-folder");
  const NotRegularFiles odd(dir.path);
  try {
    sglab::io::write_file_atomic(odd.fifo / "summary.json", "{}");
    ADD_FAILURE() << "wrote below a FIFO";
  } catch (const sglab::io::InputError& e) {
    EXPECT_TRUE(contains(e.what(), odd.fifo.string() + ": is a FIFO, not a folder")) << e.what();
  }
  EXPECT_THROW(sglab::io::write_file_atomic("", "x"), sglab::io::InputError);
  EXPECT_THROW(sglab::io::check_output_folder(""), sglab::io::InputError);
  odd.expect_untouched();
}

// Whether `dir` holds a temporary of write_files_atomic (.NAME.PID.tmp).
bool holds_temporary(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.front() == '.' && name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0)
      return true;
  }
  return false;
}

// SIGINT or SIGTERM while temporaries exist: they are removed, and the process
// still ends by the signal. A child writes 40 files of 256 KiB as one unit, over
// and over; it is signalled as soon as a temporary shows.
TEST(AtomicWrite, ASignalDuringTheWriteRemovesTheTemporaries) {
  TempDir dir("io-signal");
  std::vector<sglab::io::FileContent> files;
  for (int i = 0; i < 40; ++i)
    files.push_back({dir.path / fmt::format("set-{}.json", i), std::string(256 * 1024, 'x')});
  int rounds = 0;
  for (const int signal : {SIGINT, SIGTERM})
    for (int round = 0; round < 5; ++round) {
      const pid_t pid = ::fork();
      ASSERT_GE(pid, 0);
      if (pid == 0) {
        try {
          for (;;) sglab::io::write_files_atomic(files);
        } catch (...) {
        }
        ::_exit(3);
      }
      bool seen = false;
      for (int i = 0; i < 200000 && !seen; ++i) seen = holds_temporary(dir.path);
      ::kill(pid, signal);
      int status = 0;
      // Generous for a loaded machine: the loop ends as soon as the child does.
      for (int i = 0; i < 3000 && ::waitpid(pid, &status, WNOHANG) == 0; ++i) ::usleep(10'000);
      if (::waitpid(pid, &status, WNOHANG) == 0) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        FAIL() << "the writer did not end on signal " << signal;
      }
      EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal)
          << "signal " << signal << ", status " << status;
      EXPECT_FALSE(holds_temporary(dir.path)) << "signal " << signal << " round " << round;
      rounds += seen;
    }
  EXPECT_GT(rounds, 0) << "no temporary was ever seen while writing";
}

// ---- a folder replaced as a whole ---------------------------------------------------

TEST(ReplaceFolder, AManifestNamingPathsOutsideTheFolderIsRefused) {
  TempDir dir("io-manifest");
  const fs::path out = dir.path / "out";
  fs::create_directories(out / "sub");
  write_text(dir.path / "victim.txt", "keep");
  for (const char* entry : {"../victim.txt", "/etc/passwd", "sub/../../victim.txt", "./x", ""}) {
    write_text(out / "sglab-output.json",
               fmt::format(R"({{"format": "sglab-output", "version": 1, "command": "x", )"
                           R"("entries": ["sub/", "{}"]}})",
                           entry));
    try {
      sglab::io::check_replaceable_folder(out, "--out");
      ADD_FAILURE() << "accepted the entry " << entry;
    } catch (const sglab::io::InputError& e) {
      EXPECT_TRUE(contains(e.what(), "is not a plain relative path")) << e.what();
    }
    const fs::path staging = sglab::io::make_staging_folder(out);
    EXPECT_THROW(sglab::io::replace_folder(staging, out, "--out"), sglab::io::InputError);
    fs::remove(staging);
  }
  EXPECT_EQ(read_text(dir.path / "victim.txt"), "keep");
  EXPECT_TRUE(fs::is_directory(out / "sub"));
}

TEST(ReplaceFolder, RemovesWhatTheManifestListsAndSwapsTheNewContentIn) {
  TempDir dir("io-replace");
  const fs::path out = dir.path / "out";
  for (int run = 0; run < 3; ++run) {
    const fs::path staging = sglab::io::make_staging_folder(out);
    EXPECT_EQ(staging.parent_path(), fs::weakly_canonical(dir.path));
    fs::create_directories(staging / "logs" / "deep");
    write_text(staging / "logs" / "deep" / "a.log", fmt::format("run {}", run));
    write_text(staging / "index.md", fmt::format("run {}", run));
    sglab::io::write_output_manifest(staging, "test");
    EXPECT_EQ(sglab::io::replace_folder(staging, out, "--out"), "");
    EXPECT_EQ(read_text(out / "logs" / "deep" / "a.log"), fmt::format("run {}", run));
    const auto manifest = nlohmann::json::parse(read_text(out / "sglab-output.json"));
    EXPECT_EQ(manifest.at("entries"),
              nlohmann::json::array({"index.md", "logs/", "logs/deep/", "logs/deep/a.log"}));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1)
        << "the previous output or the staging folder is left beside it";
  }
}

TEST(OutputCommands, HeaderOverAFifoOrSymlinkExitsTwoAndLeavesItAlone) {
  TempDir dir("io-header");
  const NotRegularFiles odd(dir.path);
  const std::string sets =
      (fs::path(SGLAB_TEST_SOURCE_DIR).parent_path() / "data" / "constants").string();
  for (const fs::path& header : {odd.fifo, odd.link, odd.folder}) {
    const auto r =
        run_sglab({"constants", "--dir", sets, "--write-header", "--header", header.string()});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, header.string() + ": is a")) << r.output;
  }
  odd.expect_untouched();
}

TEST(OutputCommands, SweepOutputOverASymlinkOrIntoAFifoExitsTwo) {
  TempDir dir("io-sweep-out");
  const NotRegularFiles odd(dir.path);
  const auto sweep = [](const fs::path& out) {
    return run_sglab({"sweep", "--kappa", "1:1:1", "--cosines", "3", "--method", "punctual",
                      "--out", out.string()});
  };
  auto r = sweep(odd.fifo);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "is a FIFO, not a folder")) << r.output;
  fs::create_directories(dir.path / "out");
  fs::create_symlink(odd.target, dir.path / "out" / "summary.json");
  r = sweep(dir.path / "out");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "summary.json: is a symbolic link")) << r.output;
  odd.expect_untouched();
}

TEST(OutputCommands, EmptyPathsExitTwoNamingTheOption) {
  // Every path option, input or output. In an empty folder outside any
  // checkout: should an empty path be taken as the working directory, the
  // checkout's defaults or the compiled-in data, nothing of value is hit.
  TempDir dir("io-empty-out");
  const fs::path cwd = fs::current_path();
  fs::current_path(dir.path);
  const std::string map =
      (fs::path(SGLAB_TEST_SOURCE_DIR).parent_path() / "data" / "envmaps" / "city.exr").string();
  struct Case {
    std::vector<std::string> args;
    std::string option;
  };
  for (const Case& c : std::vector<Case>{
           {{"run", "--out", ""}, "--out"},
           {{"fit", "clamped-cosine", "--out", ""}, "--out"},
           {{"fit", "clamped-cosine", "--out", "x", "--header", ""}, "--header"},
           {{"fit", "sglab-acc", "--dry-run", "--costs", ""}, "--costs"},
           {{"constants", "--write-header", "--header", ""}, "--header"},
           {{"constants", "--dir", ""}, "--dir"},
           {{"sweep", "--out", ""}, "--out"},
           {{"stability", "--out", ""}, "--out"},
           {{"claims", "--out", ""}, "--out"},
           {{"erf", "--out", ""}, "--out"},
           {{"bench", "--out", ""}, "--out"},
           {{"pareto", "--out", ""}, "--out"},
           {{"pareto", "--costs", ""}, "--costs"},
           {{"recommend", "--kappa", "1:10", "--budget", "0.01", "--costs", ""}, "--costs"},
           {{"recommend", "--scene", "", "--budget", "0.01"}, "--scene"},
           {{"figures", "--out", ""}, "--out"},
           {{"figures", "--pareto", ""}, "--pareto"},
           {{"figures", "--costs", ""}, "--costs"},
           {{"figures", "--gnuplot", ""}, "--gnuplot"},
           {{"export", "--lang", "glsl", "--method", "hill", "--constants", ""}, "--constants"},
           {{"eval", "--method", "hill", "--points", ""}, "--points"},
           {{"reference", "--points", ""}, "--points"},
           {{"gpucost", "--out", ""}, "--out"},
           {{"envmap", "downsample", "", "out.exr"}, "IN"},
           {{"envmap", "downsample", map, ""}, "OUT"},
           {{"envmap", "irradiance", ""}, "FILE"},
           {{"envmap", "fit", "", "--lobes", "1"}, "FILE"},
           {{"envmap", "fit", map, "--lobes", "1", "--out", ""}, "--out"},
           {{"envmap", "recommend", "", "--budget", "0.1"}, "FILE"},
           {{"envmap", "recommend", map, "--budget", "0.1", "--costs", ""}, "--costs"},
           {{"envmap", "baselines", "--maps", ""}, "--maps"},
           {{"envmap", "baselines", "--out", ""}, "--out"}}) {
    const auto r = run_sglab(c.args);
    const std::string what = fmt::format("{}: {}", fmt::join(c.args, " "), r.output);
    EXPECT_EQ(r.exit_code, 2) << what;
    EXPECT_TRUE(contains(r.output, c.option + ": an empty path is not allowed")) << what;
  }
  fs::current_path(cwd);
  EXPECT_TRUE(fs::is_empty(dir.path)) << "something was written into the working directory";
}

// ---- bounded input -------------------------------------------------------------

TEST(InputFile, RefusesWhatIsNotARegularFileAndFilesOverTheLimit) {
  TempDir dir("io-input");
  const NotRegularFiles odd(dir.path);
  const std::pair<fs::path, const char*> cases[] = {
      {odd.fifo, "is a FIFO"},  // refused without blocking
      {odd.folder, "is a directory"},
      {dir.path / "absent", "no such file"}};
  for (const auto& [path, why] : cases) {
    try {
      sglab::io::read_input_file(path, 100, "a test file");
      ADD_FAILURE() << "read " << path;
    } catch (const sglab::io::InputError& e) {
      EXPECT_TRUE(contains(e.what(), path.string() + ": " + why)) << e.what();
    }
  }
  // a link to a regular file is fine
  EXPECT_EQ(sglab::io::read_input_file(odd.link, 100, "a test file"), "keep");
  EXPECT_EQ(sglab::io::read_input_file(odd.target, 4, "a test file"), "keep");  // exactly the limit
  try {
    sglab::io::read_input_file(odd.target, 3, "a test file");
    ADD_FAILURE() << "read a file over the limit";
  } catch (const sglab::io::InputError& e) {
    EXPECT_TRUE(contains(e.what(), "4 bytes, more than the 3 bytes a test file may have"))
        << e.what();
  }
}

TEST(InputFile, EveryJsonInputOfTheCommandsIsBoundedAndRegular) {
  TempDir dir("io-json-inputs");
  const NotRegularFiles odd(dir.path);
  const fs::path big = dir.path / "big.json";
  {
    std::ofstream out(big, std::ios::binary);
    const std::string spaces(1 << 20, ' ');
    for (int i = 0; i < 17; ++i) out << spaces;  // 17 MiB: above every JSON input's limit
  }
  for (const fs::path& file : {odd.fifo, odd.folder, big}) {
    const std::string f = file.string();
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"recommend", "--scene", f, "--budget", "1e-2"},
             {"pareto", "--kappa", "1:10", "--costs", f},
             {"figures", "--pareto", f, "--out", (dir.path / "figs").string()}}) {
      const auto r = run_sglab(args);
      EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.output;
      EXPECT_TRUE(contains(r.output, f + ": ")) << r.output;
    }
  }
  // A constant-set file in --dir that is a FIFO.
  const fs::path sets = dir.path / "sets";
  fs::create_directories(sets);
  ASSERT_EQ(::mkfifo((sets / "x.json").c_str(), 0600), 0);
  const auto r = run_sglab({"constants", "--dir", sets.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, (sets / "x.json").string() + ": is a FIFO")) << r.output;
  odd.expect_untouched();
}

// ---- JSON numbers out of range, named by file and key ------------------------------

TEST(JsonInput, NumbersBeyondDoubleNameTheKeyInAShortMessage) {
  const std::string huge(100'000, '7');
  for (const std::string& number : {std::string("1e400"), huge, "-" + huge}) {
    const std::string text = R"({"lights": [{"axis": [0, 0, 1], "sharpness": )" + number + "}]}";
    try {
      sglab::io::parse_json_strict(text, "scene.json");
      ADD_FAILURE() << "accepted " << number.substr(0, 20);
    } catch (const sglab::io::InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("scene.json: ", 0), 0u) << msg;
      EXPECT_TRUE(contains(msg, "'lights[0].sharpness'")) << msg;
      EXPECT_TRUE(contains(msg, "out of range (larger than any double)")) << msg;
      EXPECT_FALSE(contains(msg, "json.exception")) << msg;
      EXPECT_LT(msg.size(), 300u) << msg.substr(0, 300);
    }
  }
}

// The depth limit at its boundary: kMaxJsonDepth (64) nested containers are read, one more is
// refused naming the limit; arrays and objects count alike.
TEST(JsonInput, DepthLimitIsExactlySixtyFourLevels) {
  ASSERT_EQ(sglab::io::kMaxJsonDepth, 64);
  const auto arrays = [](int depth) {
    return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']');
  };
  const auto objects = [](int depth) {
    std::string t;
    for (int i = 1; i < depth; ++i) t += R"({"a": )";
    t += "{}";
    for (int i = 1; i < depth; ++i) t += "}";
    return t;
  };
  for (const auto& nest :
       {std::function<std::string(int)>(arrays), std::function<std::string(int)>(objects)}) {
    const auto doc = sglab::io::parse_json_strict(nest(64), "deep.json");
    const nlohmann::ordered_json* inner = &doc;
    int depth = 1;
    while (!inner->empty()) inner = inner->is_array() ? &(*inner)[0] : &(*inner)["a"], ++depth;
    EXPECT_EQ(depth, 64);
    try {
      sglab::io::parse_json_strict(nest(65), "deep.json");
      ADD_FAILURE() << "65 levels accepted";
    } catch (const sglab::io::InputError& e) {
      EXPECT_TRUE(contains(e.what(), "deep.json: ")) << e.what();
      EXPECT_TRUE(contains(e.what(), "nested deeper than 64 levels")) << e.what();
    }
  }
}

TEST(JsonInput, SceneAndConstantsFilesWithHugeNumbersExitTwoNamingFileAndKey) {
  TempDir dir("io-json-huge");
  const std::string huge(100'000, '9');
  const fs::path scene = dir.path / "scene.json";
  write_text(scene, R"({"lights": [{"axis": [0, 0, 1], "sharpness": )" + huge +
                        R"(, "amplitude": [1, 1, 1]}]})");
  auto r = run_sglab({"recommend", "--scene", scene.string(), "--budget", "1e-2"});
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 500);
  EXPECT_TRUE(contains(r.output, scene.string() + ": malformed JSON: key 'lights[0].sharpness'"))
      << r.output.substr(0, 500);
  EXPECT_LT(r.output.size(), 1000u);
  // A constant set with a coefficient of 1e400.
  const fs::path sets = dir.path / "sets";
  fs::create_directories(sets);
  const fs::path source = fs::path(SGLAB_TEST_SOURCE_DIR).parent_path() / "data" / "constants" /
                          "clamped-cosine-float.json";
  std::string set = read_text(source);
  const auto at = set.find("\"lambda\":");
  ASSERT_NE(at, std::string::npos);
  const auto value = set.find_first_of("-0123456789", at + 9);
  const auto end = set.find_first_of(",\n}", value);
  set.replace(value, end - value, "1e400");
  write_text(sets / "c.json", set);
  r = run_sglab({"constants", "--dir", sets.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, (sets / "c.json").string())) << r.output;
  EXPECT_TRUE(contains(r.output, "'coefficients.lambda': '1e400' is out of range")) << r.output;
}

// ---- whole-number options, one parser ------------------------------------------------

TEST(CountOption, ParsesDigitsOnlyWithinTheRange) {
  using sglab::io::parse_count;
  EXPECT_EQ(std::get<long long>(parse_count("4096", 1, 1000000)), 4096);
  EXPECT_EQ(std::get<long long>(parse_count("2", 2, 2)), 2);
  const std::pair<const char*, const char*> bad[] = {
      {"-1", "'-1' is not a whole number"},
      {"+5", "is not a whole number"},
      {"1e3", "is not a whole number"},
      {" 5", "is not a whole number"},
      {"", "is not a whole number"},
      {"1000001", "'1000001' is out of range (at most 1000000)"},
      {"99999999999999999999999", "is out of range (at most 1000000)"},
      {"0", "must be at least 1, got '0'"}};
  for (const auto& [text, why] : bad) {
    const auto r = parse_count(text, 1, 1000000);
    ASSERT_TRUE(std::holds_alternative<std::string>(r)) << text;
    EXPECT_TRUE(contains(std::get<std::string>(r), why)) << std::get<std::string>(r);
  }
}

TEST(CountOption, CommandsSayWhatIsWrongWithAWholeNumber) {
  const std::string scene =
      (fs::path(SGLAB_TEST_SOURCE_DIR).parent_path() / "data" / "scenes" / "studio.json").string();
  auto r = run_sglab({"recommend", "--scene", scene, "--budget", "1e-2", "--normals", "-1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "--normals")) << r.output;
  EXPECT_TRUE(contains(r.output, "'-1' is not a whole number")) << r.output;
  EXPECT_FALSE(contains(r.output, "18446744073709551615")) << r.output;
  r = run_sglab({"sweep", "--kappa", "1:1:1", "--cosines", "2147483648"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "--cosines: '2147483648' is out of range")) << r.output;
  r = run_sglab({"table", "--cosines", "2147483648"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "'2147483648' is out of range")) << r.output;
  r = run_sglab({"table", "--cosines", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "must be at least 2")) << r.output;
}

TEST(SceneInput, NegativeZeroSharpnessIsZero) {
  TempDir dir("io-negzero");
  const fs::path scene = dir.path / "s.json";
  write_text(scene,
             R"({"lights": [{"axis": [0, 0, 1], "sharpness": -0.0, "amplitude": [1, 1, 1]}]})");
  const auto r =
      run_sglab({"recommend", "--scene", scene.string(), "--budget", "1e-2", "--normals", "16"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "κ in [0, 0]")) << r.output;
  EXPECT_FALSE(contains(r.output, "[-0")) << r.output;
}

// ---- points CSV: short, escaped messages; streamed eval ------------------------------

TEST(PointsInput, ALongLineWithControlBytesIsQuotedShortAndEscaped) {
  TempDir dir("io-points-line");
  const fs::path file = dir.path / "p.csv";
  std::string line = "1,";
  line += std::string("\0\x01\x1b[2J", 6);
  line += std::string(1 << 20, 'x');  // a 1 MB line
  write_text(file, "kappa,cosine\n0.5,0\n" + line + "\n");
  for (const char* command : {"reference", "eval"}) {
    std::vector<std::string> args = {command, "--points", file.string()};
    if (std::string(command) == "eval") args.insert(args.end(), {"--method", "tokuyoshi2024"});
    const auto r = run_sglab(args);
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.output.substr(0, 500);
    EXPECT_LT(r.output.size(), 1000u) << command;
    EXPECT_TRUE(contains(r.output, file.string() + ":3: ")) << r.output.substr(0, 500);
    EXPECT_EQ(r.output.find('\0'), std::string::npos)
        << command << ": a raw NUL byte in the output";
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos)
        << command << ": a raw escape byte in the output";
  }
  // A short bad line with a NUL byte: the message escapes it.
  write_text(file, std::string("kappa,cosine\n1,0\n1,\0\n", 21));
  const auto r = run_sglab({"reference", "--points", file.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "\\x00")) << r.output;
}

TEST(PointsInput, RowsBeforeABadRowArePrintedThenExitTwo) {
  TempDir dir("io-points-bad-row");
  const fs::path file = dir.path / "p.csv";
  std::string text = "kappa,cosine\n";
  const int good = 5000;  // more than one chunk of the reference
  for (int i = 0; i < good; ++i) text += fmt::format("{},0.25\n", 1 + i);
  text += "1,2\n";  // cosine out of range
  write_text(file, text);
  for (const char* command : {"reference", "eval"}) {
    std::vector<std::string> args = {command, "--points", file.string()};
    if (std::string(command) == "eval") args.insert(args.end(), {"--method", "tokuyoshi2024"});
    const auto out = run_sglab(args, /*merge_stderr=*/false);
    EXPECT_EQ(out.exit_code, 2) << command;
    EXPECT_EQ(std::count(out.output.begin(), out.output.end(), '\n'), good + 1)
        << command;  // header and every good row
    const auto all = run_sglab(args);
    EXPECT_TRUE(contains(all.output,
                         fmt::format("{}:{}: cosine must be in [-1, 1]", file.string(), good + 2)))
        << all.output.substr(all.output.size() > 300 ? all.output.size() - 300 : 0);
  }
  // A refused file, or a bad first row: nothing at all on stdout.
  write_text(dir.path / "first.csv", "kappa,cosine\n1,2\n");
  for (const fs::path& f : {dir.path / "absent.csv", dir.path / "first.csv", dir.path})
    for (const char* command : {"reference", "eval"}) {
      std::vector<std::string> args = {command, "--points", f.string()};
      if (std::string(command) == "eval") args.insert(args.end(), {"--method", "tokuyoshi2024"});
      const auto out = run_sglab(args, /*merge_stderr=*/false);
      EXPECT_EQ(out.exit_code, 2) << command << " " << f;
      EXPECT_EQ(out.output, "") << command << " " << f;
    }
}

TEST(PointsInput, EvalInFloatRefusesKappaThatFloatCannotHold) {
  TempDir dir("io-eval-float");
  const fs::path file = dir.path / "p.csv";
  for (const auto& [kappa, why] : std::vector<std::pair<std::string, std::string>>{
           {"3.5e38", "exceeds the largest finite float"}, {"1e-50", "rounds to 0 in float"}}) {
    write_text(file, "kappa,cosine\n" + kappa + ",0.5\n");
    auto r = run_sglab({"eval", "--method", "tokuyoshi2024", "--points", file.string()});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, file.string() + ":2: kappa")) << r.output;
    EXPECT_TRUE(contains(r.output, why)) << r.output;
    EXPECT_FALSE(contains(r.output, "nan")) << r.output;
    r = run_sglab(
        {"eval", "--method", "tokuyoshi2024", "--points", file.string(), "--precision", "double"},
        false);
    EXPECT_EQ(r.exit_code, 0) << r.output;  // a double holds it
  }
  // The largest float and the smallest subnormal float are fine.
  write_text(file, "kappa,cosine\n3.4028234663852886e38,0.5\n1.401298464324817e-45,0.5\n");
  const auto r = run_sglab({"eval", "--method", "tokuyoshi2024", "--points", file.string()}, false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
