// multibody/serial_vector_ops.h — compiled replacements for the hot operations of SUNDIALS'
// serial N_Vector.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <sundials/sundials_nvector.h>

namespace flexrod::multibody {

/// Replaces the operations IDA spends its steps in (linear sums, scalings, the fused linear
/// combination and its vector-array forms, the weighted RMS norms) on the serial vector `v`
/// with this project's compiled ones. Debian 12's SUNDIALS 6.4.1 ships its serial vector
/// unoptimised (every loop index kept on the stack: about 15 instructions per element of a
/// scaling, where 2 do), and these loops were a quarter of the main job's instructions.
/// Vectors IDA clones from `v` inherit the operations. Each result is bit-identical to
/// SUNDIALS' own (the same operations in the same order per element, its special cases of the
/// linear sum kept where they round differently, the norms summed in index order); the tests
/// compare every case bit for bit.
void UseCompiledSerialOps(N_Vector v);

}  // namespace flexrod::multibody
