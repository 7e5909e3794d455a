// Files written whole or not at all (engine/io/atomic_file.h): temporaries only this process
// names and creates, only they removed; a killed run's temporaries cleared, no one else's.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/atomic_file.h"
#include "io/paths.h"
#include "test_files.h"

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
  AtomicFile file_a(dir / "x.json"), file_b(dir / "x.json");
  const fs::path a = file_a.temporary(), b = file_b.temporary();
  EXPECT_NE(a, b);
  long pid = 0;
  ASSERT_TRUE(is_temporary_name(a.filename().string(), &pid)) << a;
  EXPECT_EQ(pid, long(getpid()));
  EXPECT_TRUE(
      a.filename().string().starts_with("x.json.aeroflock-" + std::to_string(getpid()) + "-"))
      << a;
  EXPECT_TRUE(fs::is_regular_file(a));
  EXPECT_EQ(fs::file_size(a), 0u);

  EXPECT_TRUE(is_temporary_name("flock.pvd.aeroflock-12-3.tmp"));
  for (const char* other : {"x.json.tmp", "x.aeroflock-12.tmp", ".aeroflock-12-3.tmp",
                            "x.aeroflock--3.tmp", "x.aeroflock-12-.tmp", "x.aeroflock-0-3.tmp",
                            "x.aeroflock-1a-3.tmp", "x.aeroflock-12-3.tmp.bak", "x.aeroflock-12-3"})
    EXPECT_FALSE(is_temporary_name(other)) << other;
}

TEST(AtomicFile, SomeoneElsesTmpSurvivesAWriteThatFailsAndOneThatSucceeds) {
  const fs::path dir = fresh_dir("theirs");
  const fs::path path = dir / "x.json";
  write_text(dir / "x.json.tmp", "someone else's\n");
  write_text(path, "old\n");
  // A write given up (an exception before commit): the old file stays, and nothing but its own
  // temporary is removed.
  try {
    AtomicFile file(path);
    file.write("half");
    throw std::runtime_error("the writer gave up");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(read_text(path), "old\n");
  EXPECT_EQ(read_text(dir / "x.json.tmp"), "someone else's\n");
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"x.json", "x.json.tmp"}));
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

// A file size limit (RLIMIT_FSIZE) for the scope: a write past it fails with EFBIG, a real failure
// of the system call, as a full disk's ENOSPC is (tests/fake_full_disk.cpp injects those).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    rlimit lower = old_;
    lower.rlim_cur = bytes;
    EXPECT_EQ(setrlimit(RLIMIT_FSIZE, &lower), 0);
    old_handler_ = signal(SIGXFSZ, SIG_IGN);  // else the signal ends the process
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit old_{};
  sighandler_t old_handler_ = SIG_DFL;
};

TEST(AtomicFile, AFailedWriteIsReportedWithTheCallsReasonAndLeavesTheOldFile) {
  const fs::path dir = fresh_dir("efbig");
  const fs::path path = dir / "x.vtp";
  write_text(path, "old\n");
  const std::string expected = "cannot write " + path.string() + ": " + std::strerror(EFBIG);
  const std::string big(4096, 'x');
  {
    FileSizeLimit limit(1000);
    // More than the 1 MiB window at once: written through, the failing pwrite(2)'s reason at once.
    try {
      AtomicFile file(path);
      file.write(std::string(2 << 20, 'x'));
      ADD_FAILURE() << "a write past the limit did not throw";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
    // Less: held in the window, the failure met (and thrown) when it goes out, at commit().
    try {
      AtomicFile file(path);
      file.write(big);
      file.commit();
      ADD_FAILURE() << "a commit past the limit did not throw";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
    // Through the stream (as VTK writes): nothing thrown there, the reason kept for commit().
    try {
      AtomicFile file(path);
      for (int i = 0; i < 1000; ++i) file.stream() << big;
      EXPECT_TRUE(file.stream().bad());
      EXPECT_EQ(file.error(), std::strerror(EFBIG));
      file.commit();
      ADD_FAILURE() << "commit after a failed write did not throw";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
  EXPECT_EQ(read_text(path), "old\n");
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"x.vtp"}));
}

TEST(AtomicFile, TheStreamSeeksBackAndForthAsVtkDoes) {
  const fs::path dir = fresh_dir("seek");
  const fs::path path = dir / "x.txt";
  AtomicFile file(path);
  std::ostream& os = file.stream();
  os << "offset=" << std::string(9, ' ') << " ";  // room for the quoted offset, filled in below
  const std::streampos end_of_header = os.tellp();
  const std::string block(3 << 20,
                          'b');  // larger than the stream's window: written straight through
  os << block;
  const std::streampos end = os.tellp();
  os.seekp(7);
  os << "\"" << (end - end_of_header) << "\"";
  os.seekp(end);
  os << "|end";
  file.write(std::string_view("|raw"));  // after the stream's bytes
  file.commit();
  EXPECT_EQ(read_text(path), "offset=\"3145728\" " + block + "|end|raw");
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"x.txt"}));
  EXPECT_THROW(file.commit(), std::logic_error);
}

}  // namespace
}  // namespace aeroflock
