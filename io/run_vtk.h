// io/run_vtk.h — the "vtk" run writer's files (io/run_writer.h): a run's ParaView frames
// (mechanisms/drawing.h, recorded by run/vtk.h) as VTK XML UnstructuredGrid files (.vtu, ASCII,
// Float64, one per frame) with a .pvd collection whose timesteps are the sample times.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>

#include "mechanisms/drawing.h"

namespace flexrod {

/// Writes `<dir>/<stem>_NNNNNN.vtu` for every frame and then `<dir>/<stem>.pvd` (each file
/// whole: temporary + rename; the collection last, so an interrupted write never leaves a
/// collection naming missing files). Creates dir. Returns the path of the .pvd.
std::string WriteVtkSeries(const std::string& dir, const study::VtkSeries& series,
                           const std::string& stem = "run");

/// File name of frame i (without the directory).
std::string VtkFrameFileName(const std::string& stem, size_t i);

/// Path of the collection WriteVtkSeries writes.
std::string VtkCollectionPath(const std::string& dir, const std::string& stem = "run");

}  // namespace flexrod
