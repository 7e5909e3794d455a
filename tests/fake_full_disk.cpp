// A disk that fills up, for tests where no small tmpfs can be mounted, and a disk that fails one
// chosen call (tests/check_faults.py full-disk --injected, full-disk-calls). A test hook only:
// nothing in the program knows of it. Under LD_PRELOAD=libfake_full_disk.so:
//
//   AEROFLOCK_FAKE_DISK=DIR:BYTES   every write(), writev() and pwrite() to a file under DIR fails
//   with ENOSPC
//       once the regular files under DIR would hold more than BYTES. Writes that do not grow a file
//       (VTK patching its offsets) succeed; removing a file frees its bytes, as on a real disk.
//   AEROFLOCK_FAKE_DISK_FAIL=CALL:K the K-th call (from 1) of CALL (write: any of the three; fsync,
//   close or rename)
//       on a file under DIR fails with ENOSPC, as a full disk (or NFS reporting a deferred write)
//       makes it fail. close() still releases the descriptor, as Linux's does.
//   AEROFLOCK_FAKE_DISK_COUNT=FILE  at exit, "CALL N" lines to FILE: the calls of each kind made on
//       files under DIR (a test counts them, then fails each in turn), and "failed CALL PATH".
#include <dlfcn.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

enum Call { kWrite, kFsync, kClose, kRename, kCalls };
const char* const kNames[kCalls] = {"write", "fsync", "close", "rename"};
std::atomic<long> g_count[kCalls];
char g_failed[PATH_MAX + 16];

template <typename F>
F real(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

// DIR of AEROFLOCK_FAKE_DISK and its length; 0 when unset.
size_t fake_dir(const char** dir) {
  const char* spec = getenv("AEROFLOCK_FAKE_DISK");
  const char* colon = spec ? std::strrchr(spec, ':') : nullptr;
  *dir = spec;
  return colon ? size_t(colon - spec) : 0;
}

bool under_dir(const char* path) {
  const char* dir;
  const size_t n = fake_dir(&dir);
  return n > 0 && std::strncmp(path, dir, n) == 0 && path[n] == '/';
}

// The path open at `fd`, when it lies under DIR.
bool fd_under_dir(int fd, char* target) {
  char link[64];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t len = readlink(link, target, PATH_MAX - 1);
  if (len <= 0) return false;
  target[len] = '\0';
  return under_dir(target);
}

// An absolute path for `path` (relative ones from the working directory).
void absolute(const char* path, char* out, size_t size) {
  char cwd[PATH_MAX];
  const int n = path[0] == '/' || !getcwd(cwd, sizeof cwd)
                    ? snprintf(out, size, "%s", path)
                    : snprintf(out, size, "%s/%s", cwd, path);
  if (n < 0 || size_t(n) >= size) out[0] = '\0';  // too long: under no DIR
}

// Counts a call on `path` (under DIR) and whether it is the one to fail.
bool fails_now(Call call, const char* path) {
  const long k = ++g_count[call];
  const char* spec = getenv("AEROFLOCK_FAKE_DISK_FAIL");
  const size_t name_len = std::strlen(kNames[call]);
  if (!spec || std::strncmp(spec, kNames[call], name_len) != 0 || spec[name_len] != ':' ||
      atol(spec + name_len + 1) != k)
    return false;
  snprintf(g_failed, sizeof g_failed, "failed %s %s", kNames[call], path);
  return true;
}

long long g_used;

int add_size(const char* path, const struct stat* st, int type, struct FTW* ftw) {
  (void)path, (void)ftw;
  if (type == FTW_F && S_ISREG(st->st_mode)) g_used += st->st_size;
  return 0;
}

// Whether writing `n` bytes to `fd` (at `offset`, or at its offset when -1) now would overfill the
// fake disk, or is the write to fail.
bool write_fails(int fd, size_t n, off_t offset = -1) {
  char target[PATH_MAX];
  if (!fd_under_dir(fd, target)) return false;
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return false;
  if (fails_now(kWrite, target)) return true;
  const char* dir;
  const size_t dir_len = fake_dir(&dir);
  const off_t pos = offset >= 0 ? offset : lseek(fd, 0, SEEK_CUR);
  const long long end = (long long)(pos < 0 ? st.st_size : pos) + (long long)n;
  const long long growth = end > st.st_size ? end - st.st_size : 0;
  if (growth == 0) return false;
  char root[PATH_MAX];
  snprintf(root, sizeof root, "%.*s", (int)dir_len, dir);
  g_used = 0;
  nftw(root, add_size, 16, FTW_PHYS);
  return g_used + growth > atoll(dir + dir_len + 1);
}

__attribute__((destructor)) void report_counts() {
  const char* file = getenv("AEROFLOCK_FAKE_DISK_COUNT");
  if (!file) return;
  FILE* out = fopen(file, "w");
  if (!out) return;
  for (int c = 0; c < kCalls; ++c) fprintf(out, "%s %ld\n", kNames[c], g_count[c].load());
  if (g_failed[0]) fprintf(out, "%s\n", g_failed);
  fclose(out);
}

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buf, size_t n) {
  static const auto real_write = real<ssize_t (*)(int, const void*, size_t)>("write");
  if (write_fails(fd, n)) {
    errno = ENOSPC;
    return -1;
  }
  return real_write(fd, buf, n);
}

ssize_t writev(int fd, const struct iovec* iov, int count) {
  static const auto real_writev = real<ssize_t (*)(int, const struct iovec*, int)>("writev");
  size_t n = 0;
  for (int i = 0; i < count; ++i) n += iov[i].iov_len;
  if (write_fails(fd, n)) {
    errno = ENOSPC;
    return -1;
  }
  return real_writev(fd, iov, count);
}

ssize_t pwrite(int fd, const void* buf, size_t n, off_t offset) {
  static const auto real_pwrite = real<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite");
  if (write_fails(fd, n, offset)) {
    errno = ENOSPC;
    return -1;
  }
  return real_pwrite(fd, buf, n, offset);
}

ssize_t pwrite64(int fd, const void* buf, size_t n, off_t offset) {
  return pwrite(fd, buf, n, offset);
}

int fsync(int fd) {
  static const auto real_fsync = real<int (*)(int)>("fsync");
  char target[PATH_MAX];
  if (fd_under_dir(fd, target) && fails_now(kFsync, target)) {
    errno = ENOSPC;
    return -1;
  }
  return real_fsync(fd);
}

int close(int fd) {
  static const auto real_close = real<int (*)(int)>("close");
  char target[PATH_MAX];
  const bool fail = fd_under_dir(fd, target) && fails_now(kClose, target);
  const int r = real_close(fd);
  if (fail) {
    errno = ENOSPC;
    return -1;
  }
  return r;
}

int rename(const char* from, const char* to) {
  static const auto real_rename = real<int (*)(const char*, const char*)>("rename");
  char path[PATH_MAX];
  absolute(from, path, sizeof path);
  if (under_dir(path) && fails_now(kRename, path)) {
    errno = ENOSPC;
    return -1;
  }
  return real_rename(from, to);
}

}  // extern "C"
