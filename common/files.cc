// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "common/error.h"

namespace flexrod {

namespace {

void FsyncPath(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return;  // best effort: a file system without fsync still gets rename atomicity
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

namespace {

/// Writes `content` to `tmp` (fwrite and fclose checked); IoError naming `path` otherwise.
void WriteTemporary(const std::string& tmp, const std::string& content, const std::string& path) {
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw IoError(std::string(std::strerror(errno)) + ": " + tmp);
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const int write_errno = errno;
  // fclose flushes the buffer: on a full disk the error may surface only here.
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    const int e = !written ? write_errno : errno;
    std::remove(tmp.c_str());
    throw IoError(std::string(std::strerror(e)) + ": " + path);
  }
}

/// FLEXROD_FAIL_WRITE=N: the N-th file committed in this process fails as on a full disk
/// (fault injection for the tests of what survives a failed write).
void InjectedFault(const std::string& tmp, const std::string& path) {
  static const long fail_at = [] {
    const char* env = std::getenv("FLEXROD_FAIL_WRITE");
    return env ? std::atol(env) : 0L;
  }();
  static std::atomic<long> count{0};
  if (fail_at > 0 && ++count == fail_at) {
    std::remove(tmp.c_str());
    throw IoError(std::string(std::strerror(ENOSPC)) + ": " + path);
  }
}

}  // namespace

void WriteFileAtomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(tmp, content, path);
  InjectedFault(tmp, path);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw IoError("cannot rename " + tmp + " to " + path + ": " + std::strerror(e));
  }
}

void WriteFileDurable(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(tmp, content, path);
  CommitFile(tmp, path);
}

void CommitFile(const std::string& tmp, const std::string& path) {
  InjectedFault(tmp, path);
  FsyncPath(tmp, false);
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot rename " + tmp + " to " + path + ": " + ec.message());
  }
  const std::string dir = std::filesystem::path(path).parent_path().string();
  FsyncPath(dir.empty() ? "." : dir, true);
}

void EnsureDirectory(const std::string& key, const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path)) {
    throw InputError(key, path, "cannot create this directory: " + ec.message());
  }
}

void CheckCanWriteFile(const std::string& key, const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(key, path, "is a directory, not a file");
  const fs::path parent = fs::absolute(path, ec).parent_path();
  if (!fs::is_directory(parent, ec)) {
    throw InputError(key, path, "its directory " + parent.string() + " does not exist");
  }
  if (::access(parent.c_str(), W_OK) != 0) {
    throw InputError(key, path, "its directory " + parent.string() + " is not writable");
  }
}

void CheckCanCreateDirectory(const std::string& key, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec);
  if (ec) throw InputError(key, dir, "is not a usable path: " + ec.message());
  while (!fs::exists(p, ec) && p.has_parent_path() && p.parent_path() != p) p = p.parent_path();
  if (!fs::is_directory(p, ec)) {
    throw InputError(key, dir, "cannot be a directory: " + p.string() + " is not a directory");
  }
  if (::access(p.c_str(), W_OK) != 0) {
    throw InputError(key, dir, "cannot be created or written: " + p.string() + " is not writable");
  }
}

}  // namespace flexrod
