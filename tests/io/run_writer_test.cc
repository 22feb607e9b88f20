// SPDX-License-Identifier: GPL-3.0-or-later
// The run writers (io/run_writer.h) as a user reads their files: the ParaView frames of
// `--vtk` are well-formed VTU/PVD files holding the recorded frames exactly, and the writers
// write only what output.format and --vtk select.
#include "io/run_writer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "input/presets.h"
#include "io/run_vtk.h"
#include "run/run.h"
#include "tests/test_util.h"

namespace flexrod {
namespace {

namespace fs = std::filesystem;
using flexrod::test::ScratchPath;

/// Short captures from the index angle at t = 0: 500 samples at 10 kHz.
std::vector<std::string> Short(std::vector<std::string> more) {
  more.insert(more.begin(), {"sim.settle=0 s", "sim.capture=0.05 s", "sim.sample_rate=10 kHz"});
  return more;
}

// ---- files -------------------------------------------------------------------------------------
std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> v;
  std::istringstream is(text);
  double x;
  while (is >> x) v.push_back(x);
  return v;
}

/// Body of the DataArray named `name` (first match), or "" if absent. Plain string search:
/// libstdc++'s std::regex recurses once per character of a match, and a body of a few hundred
/// kB overflowed the stack under AddressSanitizer.
std::string ArrayBody(const std::string& xml, const std::string& name) {
  for (std::size_t tag = xml.find("<DataArray"); tag != std::string::npos;
       tag = xml.find("<DataArray", tag + 1)) {
    const std::size_t open_end = xml.find('>', tag);
    if (open_end == std::string::npos) break;
    if (xml.substr(tag, open_end - tag).find("Name=\"" + name + "\"") == std::string::npos)
      continue;
    const std::size_t close = xml.find("</DataArray>", open_end);
    return close == std::string::npos ? std::string()
                                      : xml.substr(open_end + 1, close - open_end - 1);
  }
  return std::string();
}

long Attribute(const std::string& xml, const std::string& attr) {
  std::smatch m;
  if (!std::regex_search(xml, m, std::regex(attr + "=\"([0-9]+)\""))) return -1;
  return std::stol(m[1].str());
}

TEST(VtkFiles, CollectionListsEveryFrameFileAndEachFileIsConsistent) {
  const fs::path dir = ScratchPath("vtk_files") / "vtk";  // the writer creates missing parents
  RunOutputOptions o;
  o.record_vtk = true;
  const Config cfg = LoadRunInput("rigid-rig", Short({}));
  const RunResult r = RunSimulation(cfg, nullptr, false, o);  // clearance joint
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r.vtk.has_value());
  WriteRun({(dir.parent_path() / "out").string(), "", dir.string()}, cfg, r);
  EXPECT_EQ(VtkCollectionPath(dir.string()), (dir / "run.pvd").string());
  const std::string pvd = Slurp(dir / "run.pvd");
  const std::regex entry("<DataSet timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
  std::vector<double> times;
  std::set<std::string> listed;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry); it != std::sregex_iterator();
       ++it) {
    times.push_back(std::stod((*it)[1].str()));
    listed.insert((*it)[2].str());
  }
  ASSERT_EQ(times.size(), r.vtk->frames.size());
  ASSERT_EQ(listed.size(), times.size());
  std::set<std::string> on_disk;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename() != "run.pvd") on_disk.insert(e.path().filename().string());
  }
  EXPECT_EQ(on_disk, listed);  // every listed file exists, nothing else (no .tmp) is left
  for (size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(times[i], r.vtk->frames[i].time);  // shortest round-trip text: exact
    if (i > 0) {
      EXPECT_GT(times[i], times[i - 1]);
    }
  }
  const study::VtkLayout& L = r.vtk->layout;
  for (size_t i = 0; i < r.vtk->frames.size(); i += 17) {
    const std::string vtu = Slurp(dir / VtkFrameFileName("run", i));
    const long np = Attribute(vtu, "NumberOfPoints"), nc = Attribute(vtu, "NumberOfCells");
    ASSERT_EQ(np, L.num_points);
    ASSERT_EQ(nc, static_cast<long>(L.cells.size()));
    const std::vector<double> xyz = Numbers(ArrayBody(vtu, "position [m]"));
    ASSERT_EQ(static_cast<long>(xyz.size()), 3 * np);
    for (long p = 0; p < np; ++p) {
      EXPECT_EQ(xyz[3 * p], r.vtk->frames[i].points[p].x());
      EXPECT_EQ(xyz[3 * p + 1], r.vtk->frames[i].points[p].y());
      EXPECT_EQ(xyz[3 * p + 2], 0.0);
    }
    for (const char* name : {"deflection [m]", "bending_stress [Pa]", "axial_stress [Pa]"}) {
      EXPECT_EQ(static_cast<long>(Numbers(ArrayBody(vtu, name)).size()), np) << name;
    }
    const std::vector<double> conn = Numbers(ArrayBody(vtu, "connectivity"));
    const std::vector<double> offsets = Numbers(ArrayBody(vtu, "offsets"));
    const std::vector<double> types = Numbers(ArrayBody(vtu, "types"));
    const std::vector<double> parts = Numbers(ArrayBody(vtu, "part"));
    ASSERT_EQ(static_cast<long>(offsets.size()), nc);
    ASSERT_EQ(static_cast<long>(types.size()), nc);
    ASSERT_EQ(static_cast<long>(parts.size()), nc);
    EXPECT_EQ(offsets.back(), static_cast<double>(conn.size()));
    for (double c : conn) EXPECT_TRUE(c >= 0 && c < np);
    for (double t : types)
      EXPECT_TRUE(t == study::kVtkLine || t == study::kVtkPolyLine || t == study::kVtkQuad);
    EXPECT_EQ(std::stod(ArrayBody(vtu, "time [s]")), r.vtk->frames[i].time);
    EXPECT_EQ(std::stod(ArrayBody(vtu, "deformation_scale [1]")), 100.0);
    EXPECT_EQ(std::stod(ArrayBody(vtu, "crank_angle [rad]")), r.vtk->frames[i].crank_angle);
  }
  fs::remove_all(dir.parent_path());
}

// output.format selects the channel files; a format not selected leaves none of its files
// behind from an earlier run in the same directory, and nothing writes VTK without --vtk.
TEST(RunWriters, WriteWhatIsSelectedAndRemoveWhatAnEarlierRunLeft) {
  const fs::path dir = ScratchPath("vtk_formats");
  RunOutputOptions o;
  o.record_vtk = true;  // recorded, but not asked for in files: no --vtk directory
  const Config csv = LoadRunInput("rigid-rig", Short({"output.format=csv"}));
  const RunResult r = RunSimulation(csv, nullptr, false, o);
  ASSERT_TRUE(r.ok());
  const double csv_bytes = WriteRun({dir.string(), "", ""}, csv, r);
  for (const char* f :
       {"summary.json", "resolved.toml", "channels.csv", "impacts.csv", "ideal/channels.csv"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "run.h5"));
  double listed = 0.0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) listed += static_cast<double>(e.file_size());
  EXPECT_EQ(csv_bytes, listed);
  const Config h5 = LoadRunInput("rigid-rig", Short({"output.format=hdf5"}));
  WriteRun({dir.string(), "", ""}, h5, r);
  EXPECT_TRUE(fs::is_regular_file(dir / "run.h5"));
  for (const char* f : {"channels.csv", "impacts.csv", "ideal/channels.csv", "ideal"})
    EXPECT_FALSE(fs::exists(dir / f)) << f;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"resolved.toml", "run.h5", "summary.json"}));
  // Without a run directory only the frames are written (Python's run(vtk=...) without out=).
  const fs::path frames = ScratchPath("vtk_frames_only");
  WriteRun({"", "", frames.string()}, h5, r);
  std::set<std::string> written;
  for (const auto& e : fs::directory_iterator(frames)) written.insert(e.path().extension());
  EXPECT_EQ(written, (std::set<std::string>{".pvd", ".vtu"}));
  fs::remove_all(frames);
  std::vector<std::string> formats;
  for (const auto& w : RunWriters()) formats.push_back(w->format());
  EXPECT_EQ(formats, (std::vector<std::string>{"json", "hdf5", "csv", "vtk"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace flexrod
