// SPDX-License-Identifier: GPL-3.0-or-later
// The "csv" run writer (io/run_writer.h): channels.csv, ideal/channels.csv, impacts.csv.
#include <filesystem>

#include "common/error.h"
#include "common/files.h"
#include "io/run_writer.h"
#include "mechanisms/impact_log.h"

namespace flexrod {
namespace {

namespace fs = std::filesystem;

void WriteRunCsv(const std::string& dir, const RunResult& run, const OutputSelection& sel,
                 const std::string& shared_twin_dir) {
  study::TimeSeries storage(1.0, 0.0);
  study::WriteCsv(SelectedView(run.channels, sel, &storage), dir + "/channels.csv");
  if (!run.impacts.empty()) study::WriteImpactCsv(run.impacts, dir + "/impacts.csv");
  if (!run.ideal) return;
  EnsureDirectory("--out", dir + "/ideal");
  const std::string path = dir + "/ideal/channels.csv";
  if (shared_twin_dir.empty()) {
    study::WriteCsv(SelectedView(*run.ideal, sel, &storage), path);
    return;
  }
  std::error_code ec;
  fs::remove(path, ec);
  const fs::path target = fs::relative(fs::absolute(shared_twin_dir + "/ideal/channels.csv"),
                                       fs::absolute(dir + "/ideal"));
  fs::create_symlink(target, path, ec);
  if (ec) throw IoError("cannot link " + path + " to " + target.string() + ": " + ec.message());
}

class CsvWriter final : public RunWriter {
 public:
  const char* format() const override { return "csv"; }
  bool Selected(const RunFileRequest& r, const OutputSelection& sel) const override {
    return !r.dir.empty() && sel.csv;
  }
  void RemoveStale(const RunFileRequest& r) const override {
    std::error_code ec;
    for (const char* stale : {"channels.csv", "impacts.csv", "ideal/channels.csv"})
      fs::remove(r.dir + "/" + stale, ec);
    fs::remove(r.dir + "/ideal", ec);  // only if empty
  }
  double Write(const RunFileRequest& r, const RunFileContext& c) const override {
    WriteRunCsv(r.dir, c.run, c.sel, r.shared_twin_dir);
    double bytes = 0.0;
    for (const char* f : {"channels.csv", "impacts.csv", "ideal/channels.csv"})
      bytes += RegularFileBytes(r.dir + "/" + f);
    return bytes;
  }
};

}  // namespace

std::unique_ptr<RunWriter> MakeCsvWriter() { return std::make_unique<CsvWriter>(); }

}  // namespace flexrod
