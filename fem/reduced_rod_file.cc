// fem/reduced_rod_file.cc — a reduced rod's HDF5 file (WriteReducedRod, ReadReducedRod): the
// rod's specification, the reduction, the basis and every reduced matrix, read back exactly.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <string>
#include <vector>

#include "common/error.h"
#include "common/hdf5.h"
#include "fem/reduced_rod.h"

namespace flexrod::fem {
namespace {

void WriteRodSpec(const h5::Node& g, const RodSpec& rod) {
  g.SetAttr("material.name", rod.material.name);
  g.SetAttr("material.source", rod.material.source);
  g.SetAttr("material.E", rod.material.youngs_modulus, "Pa");
  g.SetAttr("material.nu", rod.material.poisson_ratio, "1");
  g.SetAttr("material.rho", rod.material.density, "kg/m^3");
  g.SetAttr("material.yield", rod.material.yield_strength, "Pa");
  g.SetAttr("rod.thickness", rod.section.thickness, "m");
  g.SetAttr("rod.height", rod.section.height, "m");
  g.SetAttr("rod.bending", ToString(rod.section.in_plane));
  g.SetAttr("rod.length", rod.length, "m");
  g.SetAttr("rod.elements", rod.num_elements, "1");
  g.SetAttr("rod.element",
            rod.theory == BeamTheory::kTimoshenko ? "timoshenko" : "euler-bernoulli");
  g.SetAttr("rod.mass", rod.mass_kind == MassKind::kLumped ? "lumped" : "consistent");
  g.SetAttr("rod.dim", rod.dim == MeshDim::kSpatial ? "spatial" : "planar");
  g.SetAttr("rod.attachments", static_cast<double>(rod.attachments.size()), "1");
  for (size_t i = 0; i < rod.attachments.size(); ++i) {
    const RigidAttachment& a = rod.attachments[i];
    const std::string p = "attachment" + std::to_string(i) + ".";
    g.SetAttr(p + "name", a.name);
    g.SetAttr(p + "node", a.node, "1");
    g.SetAttr(p + "mass", a.mass, "kg");
    g.SetAttr(p + "inertia", a.inertia, "kg*m^2");
    g.SetAttr(p + "com_x", a.com_offset.x(), "m");
    g.SetAttr(p + "com_y", a.com_offset.y(), "m");
  }
}

RodSpec ReadRodSpec(const h5::Node& g) {
  RodSpec rod;
  rod.material.name = g.GetString("material.name");
  rod.material.source = g.GetString("material.source");
  rod.material.youngs_modulus = g.GetDouble("material.E");
  rod.material.poisson_ratio = g.GetDouble("material.nu");
  rod.material.density = g.GetDouble("material.rho");
  rod.material.yield_strength = g.GetDouble("material.yield");
  rod.section.thickness = g.GetDouble("rod.thickness");
  rod.section.height = g.GetDouble("rod.height");
  rod.section.in_plane = BendingAxisFromString("rod.bending", g.GetString("rod.bending"));
  rod.length = g.GetDouble("rod.length");
  rod.num_elements = static_cast<int>(g.GetDouble("rod.elements"));
  rod.theory = g.GetString("rod.element") == "timoshenko" ? BeamTheory::kTimoshenko
                                                          : BeamTheory::kEulerBernoulli;
  rod.mass_kind = g.GetString("rod.mass") == "lumped" ? MassKind::kLumped : MassKind::kConsistent;
  rod.dim = g.GetString("rod.dim") == "spatial" ? MeshDim::kSpatial : MeshDim::kPlanar;
  const int na = static_cast<int>(g.GetDouble("rod.attachments"));
  for (int i = 0; i < na; ++i) {
    const std::string p = "attachment" + std::to_string(i) + ".";
    RigidAttachment a;
    a.name = g.GetString(p + "name");
    a.node = static_cast<int>(g.GetDouble(p + "node"));
    a.mass = g.GetDouble(p + "mass");
    a.inertia = g.GetDouble(p + "inertia");
    a.com_offset = Vec2(g.GetDouble(p + "com_x"), g.GetDouble(p + "com_y"));
    rod.attachments.push_back(a);
  }
  return rod;
}

Vec IntsToVec(const std::vector<int>& v) {
  Vec out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = v[i];
  return out;
}
std::vector<int> VecToInts(const Vec& v) {
  std::vector<int> out(v.size());
  for (int i = 0; i < v.size(); ++i) out[i] = static_cast<int>(std::lround(v[i]));
  return out;
}

}  // namespace

void WriteReducedRod(const ReducedRod& rr, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    h5::Node f = h5::CreateFile(tmp);
    f.SetAttr("format", "flexrod reduced rod v3");
    WriteRodSpec(f, rr.rod);
    f.SetAttr("reduction.method", ToString(rr.reduction.method));
    f.SetAttr("reduction.modes", rr.reduction.num_modes, "1");
    f.SetAttr("reduction.cutoff", rr.reduction.cutoff_hz, "Hz");
    f.WriteVector("fixed_dofs", IntsToVec(rr.reduction.fixed_dofs), "1");
    f.WriteVector("interface_nodes", IntsToVec(rr.reduction.interface_nodes), "1");
    f.WriteMatrix("basis", rr.basis, "1", true);
    f.WriteMatrix("K", rr.K, "N/m (generalised)");
    f.WriteMatrix("M", rr.M, "kg (generalised)");
    f.SetAttr("reduction.axial_load_modes", rr.reduction.axial_load_modes ? 1.0 : 0.0, "1");
    f.SetAttr("element_axial_stiffness", rr.element_axial_stiffness, "N/m");
    f.WriteMatrix("element_Kg", Mat(rr.element_Kg), "1/m per N of axial tension");
    f.WriteVector("frequencies", rr.frequencies_hz, "Hz");
    const h5::Node in = f.CreateGroup("inertia");
    in.SetAttr("mass", rr.inertia.mass, "kg");
    in.SetAttr("J0", rr.inertia.J0, "kg*m^2");
    in.WriteVector("S0", rr.inertia.S0, "kg*m");
    in.WriteMatrix("S", rr.inertia.S, "kg");
    in.WriteVector("I1", rr.inertia.I1, "kg*m");
    in.WriteVector("Ibar", rr.inertia.Ibar, "kg*m");
    in.WriteMatrix("Mff", rr.inertia.Mff, "kg");
    in.WriteMatrix("Stilde", rr.inertia.Stilde, "kg");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    throw NumericalError("could not rename " + tmp + " to " + path);
  }
}

ReducedRod ReadReducedRod(const std::string& path) {
  const h5::Node f = h5::OpenFile(path);
  if (!f.HasAttr("format") || f.GetString("format") != "flexrod reduced rod v3") {
    throw InputError("reduced rod file", path, "is not a flexrod reduced rod (format v3)");
  }
  ReducedRod rr;
  rr.rod = ReadRodSpec(f);
  rr.reduction.method =
      ReductionMethodFromString("reduction.method", f.GetString("reduction.method"));
  rr.reduction.num_modes = static_cast<int>(f.GetDouble("reduction.modes"));
  rr.reduction.cutoff_hz = f.GetDouble("reduction.cutoff");
  rr.reduction.fixed_dofs = VecToInts(f.ReadVector("fixed_dofs"));
  rr.reduction.interface_nodes = VecToInts(f.ReadVector("interface_nodes"));
  rr.basis = f.ReadMatrix("basis");
  rr.K = f.ReadMatrix("K");
  rr.M = f.ReadMatrix("M");
  rr.reduction.axial_load_modes = f.GetDouble("reduction.axial_load_modes") != 0.0;
  rr.element_axial_stiffness = f.GetDouble("element_axial_stiffness");
  rr.element_Kg = f.ReadMatrix("element_Kg");
  rr.frequencies_hz = f.ReadVector("frequencies");
  const h5::Node in = f.OpenGroup("inertia");
  rr.inertia.mass = in.GetDouble("mass");
  rr.inertia.J0 = in.GetDouble("J0");
  rr.inertia.S0 = in.ReadVector("S0");
  rr.inertia.S = in.ReadMatrix("S");
  rr.inertia.I1 = in.ReadVector("I1");
  rr.inertia.Ibar = in.ReadVector("Ibar");
  rr.inertia.Mff = in.ReadMatrix("Mff");
  rr.inertia.Stilde = in.ReadMatrix("Stilde");
  if (rr.rod.dim == MeshDim::kPlanar) rr.nodes = PlanarNodeShapes(rr.rod, rr.basis);
  return rr;
}

}  // namespace flexrod::fem
