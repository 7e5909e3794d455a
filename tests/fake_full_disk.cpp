// A disk that fills up, for tests where no small tmpfs can be mounted (tests/check_faults.py
// full-disk --injected): LD_PRELOAD=libfake_full_disk.so AEROFLOCK_FAKE_DISK=DIR:BYTES makes every
// write() and writev() to a file under DIR fail with ENOSPC once the regular files under DIR would
// hold more than BYTES. Writes that do not grow a file (VTK patching its offsets) always succeed;
// removing a file frees its bytes, as on a real disk. A test hook only: nothing in the program
// knows of it (libstdc++'s streams, which VTK and the summary write through, call these two).
#include <dlfcn.h>
#include <ftw.h>
#include <limits.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

long long g_used;

int add_size(const char* path, const struct stat* st, int type, struct FTW* ftw) {
  (void)path, (void)ftw;
  if (type == FTW_F && S_ISREG(st->st_mode)) g_used += st->st_size;
  return 0;
}

// Whether writing `n` bytes to `fd` now would overfill the fake disk.
bool overfills(int fd, size_t n) {
  const char* spec = getenv("AEROFLOCK_FAKE_DISK");
  const char* colon = spec ? std::strrchr(spec, ':') : nullptr;
  if (!colon) return false;
  char link[64], target[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t len = readlink(link, target, sizeof target - 1);
  const size_t dir_len = (size_t)(colon - spec);
  if (len <= 0 || (size_t)len <= dir_len || strncmp(target, spec, dir_len) != 0 || target[dir_len] != '/')
    return false;
  target[len] = '\0';
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return false;
  const off_t pos = lseek(fd, 0, SEEK_CUR);
  const long long end = (long long)(pos < 0 ? st.st_size : pos) + (long long)n;
  const long long growth = end > st.st_size ? end - st.st_size : 0;
  if (growth == 0) return false;
  char dir[PATH_MAX];
  snprintf(dir, sizeof dir, "%.*s", (int)dir_len, spec);
  g_used = 0;
  nftw(dir, add_size, 16, FTW_PHYS);
  return g_used + growth > atoll(colon + 1);
}

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buf, size_t n) {
  static ssize_t (*real)(int, const void*, size_t);
  if (!real) real = reinterpret_cast<ssize_t (*)(int, const void*, size_t)>(dlsym(RTLD_NEXT, "write"));
  if (overfills(fd, n)) {
    errno = ENOSPC;
    return -1;
  }
  return real(fd, buf, n);
}

ssize_t writev(int fd, const struct iovec* iov, int count) {
  static ssize_t (*real)(int, const struct iovec*, int);
  if (!real) real = reinterpret_cast<ssize_t (*)(int, const struct iovec*, int)>(dlsym(RTLD_NEXT, "writev"));
  size_t n = 0;
  for (int i = 0; i < count; ++i) n += iov[i].iov_len;
  if (overfills(fd, n)) {
    errno = ENOSPC;
    return -1;
  }
  return real(fd, iov, count);
}

}  // extern "C"
