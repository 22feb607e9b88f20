// SPDX-License-Identifier: GPL-3.0-or-later
// The "vtk" run writer (io/run_vtk.h): ParaView frames as VTK XML files.
#include "io/run_vtk.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/files.h"
#include "io/run_writer.h"

namespace flexrod {
namespace {

using study::kVtkLine;
using study::VtkCell;
using study::VtkFrame;
using study::VtkLayout;
using study::VtkSeries;

void AppendNumber(std::string* out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  out->append(buf, res.ptr);
}

void AppendNumber(std::string* out, long v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out->append(buf, res.ptr);
}

std::string NumberText(double v) {
  std::string s;
  AppendNumber(&s, v);
  return s;
}

template <typename T>  // double or long
void AppendArray(std::string* out, const char* type, const std::string& name,
                 const std::vector<T>& v, const char* indent) {
  *out += indent;
  *out += "<DataArray type=\"";
  *out += type;
  *out += "\" Name=\"" + name + "\" format=\"ascii\">\n";
  *out += indent;
  *out += "  ";
  for (size_t i = 0; i < v.size(); ++i) {
    if (i) *out += ' ';
    AppendNumber(out, v[i]);
  }
  *out += '\n';
  *out += indent;
  *out += "</DataArray>\n";
}

void AppendFieldScalar(std::string* out, const std::string& name, double v) {
  *out += "      <DataArray type=\"Float64\" Name=\"" + name +
          "\" NumberOfTuples=\"1\" format=\"ascii\">";
  AppendNumber(out, v);
  *out += "</DataArray>\n";
}

std::string FrameVtu(const VtkSeries& series, const VtkFrame& f) {
  const VtkLayout& L = series.layout;
  std::string s;
  s.reserve(static_cast<size_t>(L.num_points) * 120 + 2048);
  s += "<?xml version=\"1.0\"?>\n";
  s += "<!-- flexrod run frame: t = " + NumberText(f.time) + " s; rod deflection drawn " +
       NumberText(series.options.scale) +
       " times (deflection from the chord of the rod's end nodes); point data unscaled, SI units "
       "-->\n";
  s += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  s += "  <UnstructuredGrid>\n";
  s += "    <FieldData>\n";
  AppendFieldScalar(&s, "time [s]", f.time);
  if (std::isfinite(f.crank_angle)) AppendFieldScalar(&s, "crank_angle [rad]", f.crank_angle);
  AppendFieldScalar(&s, "deformation_scale [1]", series.options.scale);
  s += "    </FieldData>\n";
  s += "    <Piece NumberOfPoints=\"" + std::to_string(L.num_points) + "\" NumberOfCells=\"" +
       std::to_string(L.cells.size()) + "\">\n";
  s += "      <PointData Scalars=\"deflection [m]\">\n";
  AppendArray(&s, "Float64", "deflection [m]", f.displacement, "        ");
  AppendArray(&s, "Float64", "bending_stress [Pa]", f.bending_stress, "        ");
  AppendArray(&s, "Float64", "axial_stress [Pa]", f.axial_stress, "        ");
  s += "      </PointData>\n";
  // Per cell: part, offset of its end in the connectivity, VTK type.
  std::vector<long> part, offsets, types;
  long offset = 0;
  for (const VtkCell& c : L.cells) {
    part.push_back(static_cast<long>(c.part));
    offsets.push_back(offset += static_cast<long>(c.points.size()));
    types.push_back(static_cast<long>(c.type));
  }
  s += "      <CellData Scalars=\"part\">\n";
  AppendArray(&s, "Int32", "part", part, "        ");
  s += "      </CellData>\n";
  s += "      <Points>\n";
  s += "        <DataArray type=\"Float64\" Name=\"position [m]\" NumberOfComponents=\"3\" "
       "format=\"ascii\">\n";
  for (const Vec2& p : f.points) {
    s += "          ";
    AppendNumber(&s, p.x());
    s += ' ';
    AppendNumber(&s, p.y());
    s += " 0\n";
  }
  s += "        </DataArray>\n";
  s += "      </Points>\n";
  s += "      <Cells>\n";
  s += "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const VtkCell& c : L.cells) {
    s += "          ";
    for (size_t i = 0; i < c.points.size(); ++i) {
      if (i) s += ' ';
      AppendNumber(&s, static_cast<long>(c.points[i]));
    }
    s += '\n';
  }
  s += "        </DataArray>\n";
  AppendArray(&s, "Int32", "offsets", offsets, "        ");
  AppendArray(&s, "UInt8", "types", types, "        ");
  s += "      </Cells>\n";
  s += "    </Piece>\n";
  s += "  </UnstructuredGrid>\n";
  s += "</VTKFile>\n";
  return s;
}

/// Writes RunResult::vtk (when the run recorded frames) into the directory of --vtk.
class VtkWriter final : public RunWriter {
 public:
  const char* format() const override { return "vtk"; }
  bool Selected(const RunFileRequest& r, const OutputSelection& /*sel*/) const override {
    return !r.vtk_dir.empty();
  }
  void RemoveStale(const RunFileRequest& /*r*/) const override {}
  double Write(const RunFileRequest& r, const RunFileContext& c) const override {
    if (!c.run.vtk) return 0.0;
    namespace fs = std::filesystem;
    double bytes = 0.0;
    std::error_code ec;
    const std::string pvd = WriteVtkSeries(r.vtk_dir, *c.run.vtk);
    bytes += static_cast<double>(fs::file_size(pvd, ec));
    for (size_t i = 0; i < c.run.vtk->frames.size(); ++i)
      bytes += static_cast<double>(fs::file_size(r.vtk_dir + "/" + VtkFrameFileName("run", i), ec));
    return bytes;
  }
};

}  // namespace

std::unique_ptr<RunWriter> MakeVtkWriter() { return std::make_unique<VtkWriter>(); }

std::string VtkFrameFileName(const std::string& stem, size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "_%06zu.vtu", i);
  return stem + buf;
}

std::string WriteVtkSeries(const std::string& dir, const VtkSeries& series,
                           const std::string& stem) {
  EnsureDirectory("--vtk", dir);
  std::string pvd;
  pvd += "<?xml version=\"1.0\"?>\n";
  pvd +=
      "<!-- flexrod run: " + std::to_string(series.frames.size()) + " frames at " +
      NumberText(series.frame_rate) + " Hz; timestep = time [s]; rod deflection drawn " +
      NumberText(series.options.scale) +
      " times from the chord of the rod's end nodes (deformation_scale [1] in each frame's field "
      "data) -->\n";
  pvd += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  pvd += "  <Collection>\n";
  for (size_t i = 0; i < series.frames.size(); ++i) {
    const std::string name = VtkFrameFileName(stem, i);
    WriteFileAtomic(dir + "/" + name, FrameVtu(series, series.frames[i]));
    pvd += "    <DataSet timestep=\"" + NumberText(series.frames[i].time) +
           "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  pvd += "  </Collection>\n";
  pvd += "</VTKFile>\n";
  const std::string path = VtkCollectionPath(dir, stem);
  WriteFileAtomic(path, pvd);
  return path;
}

std::string VtkCollectionPath(const std::string& dir, const std::string& stem) {
  return dir + "/" + stem + ".pvd";
}

}  // namespace flexrod
