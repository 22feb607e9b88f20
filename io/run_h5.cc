// SPDX-License-Identifier: GPL-3.0-or-later
// The "hdf5" run writer (io/run_writer.h): run.h5.
#include <filesystem>

#include "common/error.h"
#include "common/files.h"
#include "common/hdf5.h"
#include "io/run_writer.h"
#include "mechanisms/impact_log.h"
#include "sweep/sweep_store.h"

namespace flexrod {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRunFormat = "flexrod-run 1";

void WriteChannelGroup(const h5::Node& group, const study::TimeSeries& ts,
                       const OutputSelection& sel) {
  study::TimeSeries storage(1.0, 0.0);
  const study::TimeSeries& out = SelectedView(ts, sel, &storage);
  study::WriteChannels(group, out.sample_rate(), out.start_time(), static_cast<double>(sel.stride),
                       out.channels());
}

/// run.h5: written to run.h5.tmp, closed (which flushes and checks every buffered write), then
/// renamed into place.
void WriteRunH5(const std::string& dir, const Config& cfg, const RunResult& run,
                const OutputSelection& sel, const std::string& shared_twin_dir) {
  const std::string path = dir + "/run.h5", tmp = path + ".tmp";
  study::StoreOptions store;
  store.channels.clear();  // written below, without the copy a StoredRun would hold
  const double rate = run.channels.sample_rate();
  store.rate = rate / static_cast<double>(sel.stride);
  const study::StoredRun stored = study::AnalyseRun(cfg, run, store);
  try {
    h5::Node file = h5::CreateFile(tmp);
    file.SetAttr("format", kRunFormat);
    study::WriteStoredRun(file, stored, false);
    WriteChannelGroup(file.CreateGroup("channels"), run.channels, sel);
    if (run.ideal && !shared_twin_dir.empty()) {
      const std::string target =
          fs::relative(fs::absolute(shared_twin_dir + "/run.h5"), fs::absolute(dir)).string();
      file.LinkExternal("ideal", target, "/ideal");
    } else if (run.ideal) {
      WriteChannelGroup(file.CreateGroup("ideal").CreateGroup("channels"), *run.ideal, sel);
    }
    const h5::Node impacts = file.CreateGroup("impacts");
    std::string names, units;
    for (const study::Channel& c : study::ImpactColumns(run.impacts)) {
      impacts.WriteVector(
          c.name,
          Eigen::Map<const Vec>(c.values.data(), static_cast<Eigen::Index>(c.values.size())),
          c.unit);
      names += (names.empty() ? "" : ",") + c.name;
      units += (units.empty() ? "" : ",") + c.unit;
    }
    impacts.SetAttr("names", names);  // the column order, as in the other groups
    impacts.SetAttr("units", units);
    file.Close(tmp);
  } catch (const IoError& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(std::string(e.what()) + " (writing " + path + ")");
  } catch (...) {  // a bug or out of memory stays what it is; the half file goes
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  CommitFile(tmp, path);
}

class Hdf5Writer final : public RunWriter {
 public:
  const char* format() const override { return "hdf5"; }
  bool Selected(const RunFileRequest& r, const OutputSelection& sel) const override {
    return !r.dir.empty() && sel.hdf5;
  }
  void RemoveStale(const RunFileRequest& r) const override {
    std::error_code ec;
    fs::remove(r.dir + "/run.h5", ec);
  }
  double Write(const RunFileRequest& r, const RunFileContext& c) const override {
    WriteRunH5(r.dir, c.cfg, c.run, c.sel, r.shared_twin_dir);
    return RegularFileBytes(r.dir + "/run.h5");
  }
};

}  // namespace

std::unique_ptr<RunWriter> MakeHdf5Writer() { return std::make_unique<Hdf5Writer>(); }

}  // namespace flexrod
