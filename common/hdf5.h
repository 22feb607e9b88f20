// common/hdf5.h — a thin RAII layer over the HDF5 C API: files, groups, dense matrices and
// scalar/string attributes, every call checked. Matrices are stored row-major with their
// shape, so h5py reads them as numpy arrays of the same shape. Attributes carry units via a
// sibling attribute "<name>.unit" when given. What does not live here: what is stored.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

#include "common/eigen.h"

namespace flexrod::h5 {

/// An open HDF5 object id (file or group) closed on destruction. Movable only.
class Node {
 public:
  Node() = default;
  Node(long long id, bool is_file) : id_(id), is_file_(is_file) {}
  Node(Node&& o) noexcept : id_(o.id_), is_file_(o.is_file_), created_(o.created_) { o.id_ = -1; }
  Node& operator=(Node&& o) noexcept;
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  ~Node();
  long long id() const { return id_; }

  /// Closes now and checks it (a file's buffered writes fail here, e.g. on a full disk);
  /// `what` names the object in the error, with the system's reason. The destructor closes
  /// unchecked. A file CreateFile made that fails to close is removed.
  void Close(const std::string& what);
  bool HasChild(const std::string& name) const;
  /// True if `name` is an external link (LinkExternal).
  bool IsExternalLink(const std::string& name) const;
  /// `name` becomes an external link to `object` (absolute path inside the file) in `file`;
  /// a relative `file` resolves against the directory of the file holding the link.
  void LinkExternal(const std::string& name, const std::string& file,
                    const std::string& object) const;
  Node CreateGroup(const std::string& name) const;
  Node OpenGroup(const std::string& name) const;
  std::vector<std::string> Children() const;

  void WriteMatrix(const std::string& name, const Mat& m, const std::string& unit = "",
                   bool compress = false) const;
  Mat ReadMatrix(const std::string& name) const;
  void WriteVector(const std::string& name, const Vec& v, const std::string& unit = "",
                   bool compress = false) const;
  Vec ReadVector(const std::string& name) const;
  /// A vector to write without copying it: name, "unit" attribute ("" = none), its values.
  struct VectorView {
    std::string name, unit;
    const double* data;
    std::size_t size;
  };
  /// Writes each vector as WriteVector(..., compress = true) does (chunks of up to 65536 rows,
  /// byte shuffle, deflate), compressing the chunks on `threads` threads (0 = one per core);
  /// the bytes written do not depend on the number of threads.
  void WriteCompressedVectors(const std::vector<VectorView>& vectors, unsigned threads = 0) const;

  void SetAttr(const std::string& name, double value, const std::string& unit = "") const;
  void SetAttr(const std::string& name, const std::string& value) const;
  double GetDouble(const std::string& name) const;
  std::string GetString(const std::string& name) const;
  bool HasAttr(const std::string& name) const;

 private:
  friend Node CreateFile(const std::string& path);
  long long id_{-1};
  bool is_file_{false};
  bool created_{false};       ///< a file CreateFile made (removed if it fails to close)
  long failures_at_open_{0};  ///< failed HDF5 calls before it was created
};

/// Creates (truncates) a file.
Node CreateFile(const std::string& path);
/// Opens an existing file read-only, or read-write.
Node OpenFile(const std::string& path, bool writable = false);
/// True if a file is still held open by HDF5 after its close failed (a full disk under a file
/// opened to append to): HDF5's clean-up at exit would crash on it, so the process must leave
/// without it (app/cli.cc ends with std::_Exit then).
bool CloseFailed();

}  // namespace flexrod::h5
