// signals/signals_extrema.h — the one rule flexrod uses to call a sample a local maximum or
// minimum of a sampled sequence, shared by the acceleration turning points ("inflection
// points", signals/signals.h) and the spectrum peaks (signals/signals_spectrum.h). Only the rule
// lives here; what is stored about each extremum is up to the callers.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace flexrod::study {

/// Local maxima of x above a floor. A plateau is a maximal run x[a] = x[a+1] = ... = x[b]
/// (a single sample is a plateau with a = b). The plateau is a local maximum if
///     a ≥ 1,  b ≤ n − 2,  x[a−1] < x[a]  and  x[b+1] < x[b],
/// and it is reported once, at its first sample a, if x[a] > floor (strictly). Hence:
/// * the first and last samples are never maxima (one neighbour is unknown), nor is a plateau
///   touching either end;
/// * a flat step on a monotone staircase (x[a−1] < x[a], x[b+1] > x[b] or the reverse) is not
///   a maximum;
/// * NaN samples compare false and therefore never start or extend a maximum.
/// Clears *maxima, then appends the indices in increasing order. O(n), allocates only if
/// *maxima must grow.
void FindLocalMaxima(std::span<const double> x, double floor, std::vector<std::size_t>* maxima);

/// Local minima of x below a ceiling: the mirror image of FindLocalMaxima
/// (x[a−1] > x[a] = ... = x[b] < x[b+1], reported at a if x[a] < ceiling).
void FindLocalMinima(std::span<const double> x, double ceiling, std::vector<std::size_t>* minima);

}  // namespace flexrod::study
