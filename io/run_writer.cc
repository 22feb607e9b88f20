// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/run_writer.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "common/files.h"
#include "sweep/sweep_matrix.h"

namespace flexrod {

// The writers, each defined in its own file.
std::unique_ptr<RunWriter> MakeJsonWriter();  // io/run_json.cc
std::unique_ptr<RunWriter> MakeHdf5Writer();  // io/run_h5.cc
std::unique_ptr<RunWriter> MakeCsvWriter();   // io/run_csv.cc
std::unique_ptr<RunWriter> MakeVtkWriter();   // io/run_vtk.cc

const std::vector<std::unique_ptr<RunWriter>>& RunWriters() {
  static const std::vector<std::unique_ptr<RunWriter>> writers = [] {
    std::vector<std::unique_ptr<RunWriter>> w;
    w.push_back(MakeJsonWriter());
    w.push_back(MakeHdf5Writer());
    w.push_back(MakeCsvWriter());
    w.push_back(MakeVtkWriter());
    return w;
  }();
  return writers;
}

double WriteRun(const RunFileRequest& r, const Config& cfg, const RunResult& run) {
  const OutputSelection sel = ReadOutputSelection(cfg, cfg.Quantity("sim.sample_rate"), nullptr);
  if (!r.dir.empty()) {
    EnsureDirectory("--out", r.dir);
    for (const auto& w : RunWriters()) w->RemoveStale(r);
  }
  const RunFileContext c{cfg, run, sel};
  double bytes = 0.0;
  for (const auto& w : RunWriters()) {
    if (w->Selected(r, sel)) bytes += w->Write(r, c);
  }
  return bytes;
}

std::function<bool(const std::string&)> ChannelsTheFilesRead(const Config& cfg) {
  return [&cfg, sel = std::optional<OutputSelection>(),
          analysis = study::StoreOptions().poincare_channels](const std::string& name) mutable {
    if (!sel) sel = ReadOutputSelection(cfg, cfg.Quantity("sim.sample_rate"), nullptr);
    return Selects(*sel, name) ||
           std::find(analysis.begin(), analysis.end(), name) != analysis.end();
  };
}

study::TimeSeries SelectChannels(const study::TimeSeries& ts, const OutputSelection& sel) {
  study::TimeSeries out(ts.sample_rate() / static_cast<double>(sel.stride), ts.start_time());
  for (const study::Channel& c : ts.channels()) {
    if (!Selects(sel, c.name)) continue;
    std::vector<double> v;
    v.reserve(c.values.size() / sel.stride + 1);
    for (std::size_t i = 0; i < c.values.size(); i += sel.stride) v.push_back(c.values[i]);
    out.AddChannel(c.name, c.unit, std::move(v));
  }
  return out;
}

const study::TimeSeries& SelectedView(const study::TimeSeries& ts, const OutputSelection& sel,
                                      study::TimeSeries* storage) {
  if (!sel.standard && sel.channels.empty() && sel.stride == 1) return ts;
  *storage = SelectChannels(ts, sel);
  return *storage;
}

double RegularFileBytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(path, ec))) return 0.0;
  const auto size = fs::file_size(path, ec);
  return ec ? 0.0 : static_cast<double>(size);
}

}  // namespace flexrod
