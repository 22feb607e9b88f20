// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals_extrema.h"

#include <functional>

namespace flexrod::study {
namespace {

// `beyond(u, v)` is "u is strictly beyond v" in the search direction (> for maxima, < for
// minima); `passes(v)` is the floor/ceiling test.
template <typename Beyond, typename Passes>
void FindPlateauExtrema(std::span<const double> x, Beyond beyond, Passes passes,
                        std::vector<std::size_t>* out) {
  out->clear();
  const std::size_t n = x.size();
  std::size_t i = 1;
  while (i + 1 < n) {
    if (!beyond(x[i], x[i - 1])) {
      ++i;
      continue;
    }
    // x[i] rises beyond its left neighbour: walk to the end b of its plateau.
    std::size_t b = i;
    while (b + 1 < n && x[b + 1] == x[i]) ++b;
    if (b + 1 < n && beyond(x[i], x[b + 1]) && passes(x[i])) out->push_back(i);
    i = b + 1;  // x[b] is the left neighbour of the next candidate
  }
}

}  // namespace

void FindLocalMaxima(std::span<const double> x, double floor, std::vector<std::size_t>* maxima) {
  FindPlateauExtrema(
      x, std::greater<double>(), [floor](double v) { return v > floor; }, maxima);
}

void FindLocalMinima(std::span<const double> x, double ceiling, std::vector<std::size_t>* minima) {
  FindPlateauExtrema(
      x, std::less<double>(), [ceiling](double v) { return v < ceiling; }, minima);
}

}  // namespace flexrod::study
