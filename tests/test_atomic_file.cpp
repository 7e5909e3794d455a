// Files written whole or not at all (engine/io/atomic_file.h): temporaries only this process
// names and creates, only they removed; a killed run's temporaries cleared, no one else's.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "test_files.h"
#include "io/atomic_file.h"
#include "io/paths.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) { return testing::fresh_dir("atomic_" + name, true); }
using testing::read_text;

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

// A PID that no process has now: a child's, once it has exited and been waited for.
long dead_pid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

TEST(AtomicFile, TemporariesAreNewNamesOfThisProcess) {
  const fs::path dir = fresh_dir("names");
  const fs::path a = create_temporary(dir / "x.json");
  const fs::path b = create_temporary(dir / "x.json");
  EXPECT_NE(a, b);
  long pid = 0;
  ASSERT_TRUE(is_temporary_name(a.filename().string(), &pid)) << a;
  EXPECT_EQ(pid, long(getpid()));
  EXPECT_TRUE(a.filename().string().starts_with("x.json.aeroflock-" + std::to_string(getpid()) + "-")) << a;
  EXPECT_TRUE(fs::is_regular_file(a));
  EXPECT_EQ(fs::file_size(a), 0u);

  EXPECT_TRUE(is_temporary_name("flock.pvd.aeroflock-12-3.tmp"));
  for (const char* other : {"x.json.tmp", "x.aeroflock-12.tmp", ".aeroflock-12-3.tmp", "x.aeroflock--3.tmp",
                            "x.aeroflock-12-.tmp", "x.aeroflock-0-3.tmp", "x.aeroflock-1a-3.tmp",
                            "x.aeroflock-12-3.tmp.bak", "x.aeroflock-12-3"})
    EXPECT_FALSE(is_temporary_name(other)) << other;
}

TEST(AtomicFile, SomeoneElsesTmpSurvivesAWriteThatFailsAndOneThatSucceeds) {
  const fs::path dir = fresh_dir("theirs");
  const fs::path path = dir / "x.json";
  write_text(dir / "x.json.tmp", "someone else's\n");
  write_text(path, "old\n");
  // A write that fails: the old file stays, and nothing but its own temporary is removed.
  EXPECT_THROW(write_file_atomically(path, [](const fs::path& tmp) {
                 write_text(tmp, "half");
                 throw std::runtime_error("No space left on device");
               }),
               std::runtime_error);
  EXPECT_EQ(read_text(path), "old\n");
  EXPECT_EQ(read_text(dir / "x.json.tmp"), "someone else's\n");
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"x.json", "x.json.tmp"}));
  // The error names the file, not the temporary.
  try {
    write_file_atomically(path, [](const fs::path&) { throw std::runtime_error("No space left on device"); });
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write " + path.string() + ": No space left on device");
  }
  write_text_atomically(path, "new\n");
  EXPECT_EQ(read_text(path), "new\n");
  EXPECT_EQ(read_text(dir / "x.json.tmp"), "someone else's\n");
  // Checking the path before a run probes with a temporary of its own, too.
  check_output_path(path, "--summary", {".json"});
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"x.json", "x.json.tmp"}));
  EXPECT_EQ(read_text(dir / "x.json.tmp"), "someone else's\n");
}

TEST(AtomicFile, AKilledRunsTemporariesAreRemovedNoOneElses) {
  const fs::path dir = fresh_dir("stale");
  const std::string dead = std::to_string(dead_pid());
  const std::string live = std::to_string(getpid());
  const std::string stale = "x.json.aeroflock-" + dead + "-4.tmp";
  const std::set<std::string> kept = {
      "x.json.aeroflock-" + live + "-4.tmp",  // a running process's
      "y.json.aeroflock-" + dead + "-4.tmp",  // another file's (with the prefix x.json.)
      "x.json.tmp", "x.json.aeroflock-" + dead + ".tmp", "notes.txt"};
  for (const std::string& name : kept) write_text(dir / name, "keep\n");
  write_text(dir / stale, "half a summary");
  EXPECT_EQ(remove_stale_temporaries(dir, "x.json."), 1u);
  EXPECT_EQ(names_in(dir), kept);
  // Without a prefix, every dead process's temporary in the directory.
  EXPECT_EQ(remove_stale_temporaries(dir), 1u);
  EXPECT_FALSE(fs::exists(dir / ("y.json.aeroflock-" + dead + "-4.tmp")));
  EXPECT_EQ(remove_stale_temporaries(dir / "no-such-dir"), 0u);
  // check_output_path clears the file's own stale temporaries before a run.
  write_text(dir / stale, "half a summary");
  check_output_path(dir / "x.json", "--summary", {".json"});
  EXPECT_FALSE(fs::exists(dir / stale));
  EXPECT_TRUE(fs::exists(dir / ("x.json.aeroflock-" + live + "-4.tmp")));
}

}  // namespace
}  // namespace aeroflock
