// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/hdf5.h"

#include <hdf5.h>
#include <libdeflate.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <thread>

#include "common/error.h"

namespace flexrod::h5 {
namespace {

constexpr unsigned kDeflateLevel = 1;
constexpr hsize_t kChunkRows = 65536;

/// The operating system's reason for the failure on HDF5's error stack (the file drivers
/// record it as "error message = '<strerror>'"), or "" if there is none.
std::string SystemReason() {
  std::string reason;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        const std::string desc = e->desc != nullptr ? e->desc : "";
        const std::string tag = "error message = '";
        const size_t p = desc.find(tag);
        if (p != std::string::npos) {
          const size_t q = desc.find('\'', p + tag.size());
          *static_cast<std::string*>(data) = desc.substr(p + tag.size(), q - p - tag.size());
        }
        return 0;
      },
      &reason);
  return reason;
}

/// HDF5 calls other than reads that failed so far on this thread (a Node notes the count at its
/// file's creation; a file is written, and closed, on the thread that created it).
thread_local long g_failures = 0;

[[noreturn]] void Fail(const char* call, const std::string& what) {
  // A failed read (a missing attribute, a file that is not a store) is an answer, not a failed
  // write: only the others count against the files open on this thread.
  const std::string c = call;
  const bool read = c.find("open") != std::string::npos || c.find("read") != std::string::npos ||
                    c.find("get") != std::string::npos || c.find("iterate") != std::string::npos;
  if (!read) ++g_failures;
  const std::string reason = SystemReason();
  H5Eclear2(H5E_DEFAULT);
  throw IoError(std::string("HDF5 ") + call + " failed for '" + what + "'" +
                (reason.empty() ? "" : ": " + reason));
}

hid_t Check(hid_t id, const char* call, const std::string& what) {
  if (id < 0) Fail(call, what);
  return id;
}
void CheckStatus(herr_t st, const char* call, const std::string& what) {
  if (st < 0) Fail(call, what);
}

std::atomic<bool> g_close_failed{false};

/// Closes a file; false, with the system's reason in *reason, if it fails (its buffered writes
/// cannot be flushed: a full disk). A failed H5Fclose leaves HDF5 (1.10) holding a half-freed
/// file whose metadata cache cannot be flushed again ("slist already enabled"), and its
/// clean-up at exit crashes on it. So a file flexrod created (`created`) that a write failed on
/// since (`write_failed`) is truncated through its descriptor first, which frees its blocks, so
/// that the close (writing the little metadata left) succeeds; it is then removed: what failed to
/// be written is not kept half written. A file opened to append to (a sweep store) is never
/// truncated: what it held stays; if its close fails, CloseFailed() says so.
bool CloseFile(hid_t id, bool created, bool write_failed, std::string* reason) {
  std::string path;
  if (created) {
    path.assign(4096, '\0');
    const ssize_t n = H5Fget_name(id, path.data(), path.size());
    path.resize(n > 0 ? static_cast<size_t>(n) : 0);
  }
  if (created && write_failed) {
    void* handle = nullptr;
    if (H5Fget_vfd_handle(id, H5P_DEFAULT, &handle) >= 0 && handle != nullptr &&
        ftruncate(*static_cast<int*>(handle), 0) != 0) {
      // Nothing could be freed: the close below may fail as the write did.
    }
  }
  bool failed = write_failed;
  if (H5Fclose(id) < 0) {
    if (reason != nullptr) *reason = SystemReason();
    failed = true;
    g_close_failed = true;
  }
  H5Eclear2(H5E_DEFAULT);
  if (failed && !path.empty()) std::remove(path.c_str());
  return !failed;
}

struct Handle {  // closes any hid_t with the given closer
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

/// Chunks of up to kChunkRows rows, byte shuffle, deflate: smooth float64 signals share their
/// high-order bytes, which the shuffle groups so that deflate finds them. Level 1: the higher
/// levels cost several times the time for a few percent of size on such data.
void SetCompressed(hid_t plist, int rank, const hsize_t* dims, const std::string& name) {
  hsize_t chunk[2] = {std::max<hsize_t>(std::min<hsize_t>(dims[0], kChunkRows), 1),
                      rank > 1 ? std::max<hsize_t>(dims[1], 1) : 1};
  CheckStatus(H5Pset_chunk(plist, rank, chunk), "H5Pset_chunk", name);
  CheckStatus(H5Pset_shuffle(plist), "H5Pset_shuffle", name);
  CheckStatus(H5Pset_deflate(plist, kDeflateLevel), "H5Pset_deflate", name);
}

/// The "unit" string attribute of a dataset.
void WriteUnit(hid_t set, const std::string& unit, const std::string& name) {
  Handle ts{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(ts.id, unit.size());
  Handle as{H5Screate(H5S_SCALAR), H5Sclose};
  Handle attr{Check(H5Acreate2(set, "unit", ts.id, as.id, H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2",
                    name + ".unit"),
              H5Aclose};
  CheckStatus(H5Awrite(attr.id, ts.id, unit.c_str()), "H5Awrite", name + ".unit");
}

void SilenceErrors() {  // per thread: a thread-safe HDF5 keeps an error stack per thread
  thread_local bool done = false;
  if (!done) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    done = true;
  }
}

}  // namespace

Node& Node::operator=(Node&& o) noexcept {
  if (this != &o) {
    this->~Node();
    id_ = o.id_;
    is_file_ = o.is_file_;
    created_ = o.created_;
    failures_at_open_ = o.failures_at_open_;
    o.id_ = -1;
  }
  return *this;
}

Node::~Node() {
  if (id_ < 0) return;
  if (is_file_) {
    CloseFile(id_, created_, g_failures != failures_at_open_, nullptr);
  } else {
    H5Gclose(id_);
  }
  id_ = -1;
}

void Node::Close(const std::string& what) {
  if (id_ < 0) return;
  const hid_t id = id_;
  id_ = -1;
  if (is_file_) {
    // Flushes every buffered write: a full disk or a failed write surfaces here.
    std::string reason;
    if (!CloseFile(id, created_, g_failures != failures_at_open_, &reason)) {
      throw IoError("HDF5 H5Fclose failed for '" + what + "'" +
                    (reason.empty() ? "" : ": " + reason));
    }
  } else {
    CheckStatus(H5Gclose(id), "H5Gclose", what);
  }
}

void Node::LinkExternal(const std::string& name, const std::string& file,
                        const std::string& object) const {
  CheckStatus(
      H5Lcreate_external(file.c_str(), object.c_str(), id_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
      "H5Lcreate_external", name);
}

Node CreateFile(const std::string& path) {
  SilenceErrors();
  Node file(
      Check(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "H5Fcreate", path),
      true);
  file.created_ = true;
  file.failures_at_open_ = g_failures;
  return file;
}

bool CloseFailed() { return g_close_failed; }

Node OpenFile(const std::string& path, bool writable) {
  SilenceErrors();
  return Node(Check(H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT),
                    "H5Fopen", path),
              true);
}

bool Node::HasChild(const std::string& name) const {
  return H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0;
}

bool Node::IsExternalLink(const std::string& name) const {
  H5L_info_t info;
  return H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0 &&
         H5Lget_info(id_, name.c_str(), &info, H5P_DEFAULT) >= 0 && info.type == H5L_TYPE_EXTERNAL;
}

Node Node::CreateGroup(const std::string& name) const {
  return Node(Check(H5Gcreate2(id_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Gcreate2", name),
              false);
}

Node Node::OpenGroup(const std::string& name) const {
  return Node(Check(H5Gopen2(id_, name.c_str(), H5P_DEFAULT), "H5Gopen2", name), false);
}

std::vector<std::string> Node::Children() const {
  std::vector<std::string> names;
  auto cb = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  CheckStatus(H5Literate(id_, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &names), "H5Literate",
              "children");
  return names;
}

void Node::WriteMatrix(const std::string& name, const Mat& m, const std::string& unit,
                       bool compress) const {
  const hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  Handle space{Check(H5Screate_simple(2, dims, nullptr), "H5Screate_simple", name), H5Sclose};
  Handle plist{Check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", name), H5Pclose};
  if (compress && m.size() > 0) SetCompressed(plist.id, 2, dims, name);
  Handle set{Check(H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, plist.id,
                              H5P_DEFAULT),
                   "H5Dcreate2", name),
             H5Dclose};
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = m;
  if (m.size() > 0) {
    CheckStatus(H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rm.data()),
                "H5Dwrite", name);
  }
  if (!unit.empty()) WriteUnit(set.id, unit, name);
}

Mat Node::ReadMatrix(const std::string& name) const {
  Handle set{Check(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), "H5Dopen2", name), H5Dclose};
  Handle space{Check(H5Dget_space(set.id), "H5Dget_space", name), H5Sclose};
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 1 || rank > 2) throw IoError("HDF5 dataset '" + name + "' is not a matrix");
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  if (rank == 1) dims[1] = 1;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm(dims[0], dims[1]);
  if (rm.size() > 0) {
    CheckStatus(H5Dread(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rm.data()),
                "H5Dread", name);
  }
  return rm;
}

void Node::WriteVector(const std::string& name, const Vec& v, const std::string& unit,
                       bool compress) const {
  if (compress && v.size() > 0) {
    WriteCompressedVectors({{name, unit, v.data(), static_cast<std::size_t>(v.size())}}, 1);
    return;
  }
  const hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
  Handle space{Check(H5Screate_simple(1, dims, nullptr), "H5Screate_simple", name), H5Sclose};
  Handle set{Check(H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   "H5Dcreate2", name),
             H5Dclose};
  if (v.size() > 0) {
    CheckStatus(H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
                "H5Dwrite", name);
  }
  if (!unit.empty()) WriteUnit(set.id, unit, name);
}

void Node::WriteCompressedVectors(const std::vector<VectorView>& vectors, unsigned threads) const {
  // Every chunk is filtered here as HDF5's own pipeline would (shuffle, then deflate at
  // kDeflateLevel in the zlib format, which H5Z's deflate filter reads), so that the chunks can
  // be compressed in parallel and written directly; readers see ordinary filtered data. The
  // deflate is libdeflate's, which took less CPU than zlib's compress2 at the same level, for
  // slightly fewer bytes, on the main job's channels when it replaced it (the commit says how
  // much).
  struct Chunk {
    std::size_t vector, first;  // vector index, first element
    std::vector<unsigned char> bytes;
  };
  std::vector<Chunk> chunks;
  std::vector<hsize_t> chunk_rows(vectors.size(), 1);
  for (std::size_t k = 0; k < vectors.size(); ++k) {
    chunk_rows[k] = std::max<hsize_t>(std::min<hsize_t>(vectors[k].size, kChunkRows), 1);
    for (std::size_t i = 0; i < vectors[k].size; i += chunk_rows[k]) chunks.push_back({k, i, {}});
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  auto work = [&] {
    std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)> deflater(
        libdeflate_alloc_compressor(kDeflateLevel), libdeflate_free_compressor);
    if (!deflater) {
      failed = true;
      return;
    }
    std::vector<unsigned char> shuffled;
    for (std::size_t c = next++; c < chunks.size(); c = next++) {
      Chunk& ch = chunks[c];
      const VectorView& v = vectors[ch.vector];
      const std::size_t rows = chunk_rows[ch.vector];
      const std::size_t have = std::min(rows, v.size - ch.first);
      // A partial last chunk is stored whole, its tail filled with the fill value 0.
      shuffled.assign(rows * sizeof(double), 0);
      const auto* src = reinterpret_cast<const unsigned char*>(v.data + ch.first);
      for (std::size_t i = 0; i < have; ++i) {
        for (std::size_t b = 0; b < sizeof(double); ++b) shuffled[b * rows + i] = src[i * 8 + b];
      }
      ch.bytes.resize(libdeflate_zlib_compress_bound(deflater.get(), shuffled.size()));
      const std::size_t size = libdeflate_zlib_compress(
          deflater.get(), shuffled.data(), shuffled.size(), ch.bytes.data(), ch.bytes.size());
      if (size == 0) {  // did not fit the bound: cannot happen
        failed = true;
        return;
      }
      ch.bytes.resize(size);
    }
  };
  const unsigned n = std::max(
      1u, std::min<unsigned>(threads ? threads : std::max(1u, std::thread::hardware_concurrency()),
                             static_cast<unsigned>(chunks.size())));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failed) throw IoError("libdeflate could not compress a chunk of the HDF5 file");
  std::size_t c = 0;
  for (std::size_t k = 0; k < vectors.size(); ++k) {
    const VectorView& v = vectors[k];
    const hsize_t dims[1] = {static_cast<hsize_t>(v.size)};
    Handle space{Check(H5Screate_simple(1, dims, nullptr), "H5Screate_simple", v.name), H5Sclose};
    Handle plist{Check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", v.name), H5Pclose};
    if (v.size > 0) SetCompressed(plist.id, 1, dims, v.name);
    Handle set{Check(H5Dcreate2(id_, v.name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT,
                                plist.id, H5P_DEFAULT),
                     "H5Dcreate2", v.name),
               H5Dclose};
    for (; c < chunks.size() && chunks[c].vector == k; ++c) {
      const hsize_t offset[1] = {static_cast<hsize_t>(chunks[c].first)};
      CheckStatus(H5Dwrite_chunk(set.id, H5P_DEFAULT, 0, offset, chunks[c].bytes.size(),
                                 chunks[c].bytes.data()),
                  "H5Dwrite_chunk", v.name);
    }
    if (!v.unit.empty()) WriteUnit(set.id, v.unit, v.name);
  }
}

Vec Node::ReadVector(const std::string& name) const {
  const Mat m = ReadMatrix(name);
  return Eigen::Map<const Vec>(m.data(), m.size());
}

void Node::SetAttr(const std::string& name, double value, const std::string& unit) const {
  Handle as{H5Screate(H5S_SCALAR), H5Sclose};
  if (H5Aexists(id_, name.c_str()) > 0) H5Adelete(id_, name.c_str());
  Handle attr{Check(H5Acreate2(id_, name.c_str(), H5T_IEEE_F64LE, as.id, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Acreate2", name),
              H5Aclose};
  CheckStatus(H5Awrite(attr.id, H5T_NATIVE_DOUBLE, &value), "H5Awrite", name);
  if (!unit.empty()) SetAttr(name + ".unit", unit);
}

void Node::SetAttr(const std::string& name, const std::string& value) const {
  Handle ts{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(ts.id, std::max<size_t>(value.size(), 1));
  Handle as{H5Screate(H5S_SCALAR), H5Sclose};
  if (H5Aexists(id_, name.c_str()) > 0) H5Adelete(id_, name.c_str());
  Handle attr{Check(H5Acreate2(id_, name.c_str(), ts.id, as.id, H5P_DEFAULT, H5P_DEFAULT),
                    "H5Acreate2", name),
              H5Aclose};
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  CheckStatus(H5Awrite(attr.id, ts.id, padded.c_str()), "H5Awrite", name);
}

bool Node::HasAttr(const std::string& name) const { return H5Aexists(id_, name.c_str()) > 0; }

double Node::GetDouble(const std::string& name) const {
  Handle attr{Check(H5Aopen(id_, name.c_str(), H5P_DEFAULT), "H5Aopen", name), H5Aclose};
  double v = 0.0;
  CheckStatus(H5Aread(attr.id, H5T_NATIVE_DOUBLE, &v), "H5Aread", name);
  return v;
}

std::string Node::GetString(const std::string& name) const {
  Handle attr{Check(H5Aopen(id_, name.c_str(), H5P_DEFAULT), "H5Aopen", name), H5Aclose};
  Handle type{Check(H5Aget_type(attr.id), "H5Aget_type", name), H5Tclose};
  const size_t size = H5Tget_size(type.id);
  std::string s(size, '\0');
  Handle mem{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(mem.id, size);
  CheckStatus(H5Aread(attr.id, mem.id, s.data()), "H5Aread", name);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

}  // namespace flexrod::h5
