// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
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

void WriteFileAtomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const int write_errno = errno;
  // fclose flushes the buffer: on a full disk the error may surface only here.
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    const int e = !written ? write_errno : errno;
    std::remove(tmp.c_str());
    throw std::runtime_error(std::string(std::strerror(e)) + ": " + path);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + std::strerror(e));
  }
}

void CommitFile(const std::string& tmp, const std::string& path) {
  FsyncPath(tmp, false);
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + ec.message());
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

}  // namespace flexrod
