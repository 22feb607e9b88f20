// sweep/sweep_matrix.h — what a sweep runs: the matrix file (a base input with overrides,
// axes crossed with each other, optional explicit combinations, and the store options), its
// expansion into numbered runs, each run's Config, the run fingerprint that makes a sweep
// resumable (a finished run is found again by it), and the reduced-rod key that lets runs
// share one reduced rod. The matrix format is documented in docs/sweeps.md; the thesis's
// Table 2 is the built-in matrix "sweep-table2" (examples/sweep-table2.toml).
// Every key and value is validated here, with InputError naming key, value and rule, before a
// sweep writes anything. What does not live here: running runs (sweep/sweep.h) and the
// results store (sweep/sweep_store.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input/config.h"
#include "signals/signals.h"

namespace flexrod::study {

/// One input key with its text value, as the user wrote it ("drive.speed", "110 rpm").
struct Assignment {
  std::string key;
  std::string value;
  bool operator==(const Assignment&) const = default;
};

/// What each run keeps in the store beyond its summary (matrix section [store]).
struct StoreOptions {
  /// Channels stored as time series (decimated to `rate`); every analysis uses the full rate.
  std::vector<std::string> channels{"crank_angle", "slider_acceleration"};
  double rate{10000.0};  ///< rate of the stored channels [Hz], > 0
  Window spectrum_window{Window::kFlatTop};
  double spectrum_max{5000.0};                ///< highest stored spectrum frequency [Hz], > 0
  double inflection_floor{kInflectionFloor};  ///< noise floor of the turning points [m/s^2], >= 0
  /// Channels sampled at the index crossings (those a run does not have are left out).
  std::vector<std::string> poincare_channels{"slider_position", "slider_velocity",
                                             "slider_acceleration", "crank_speed"};
  /// Canonical one-line text (enters the run fingerprint: other options, other results).
  std::string Describe() const;
};

/// One run of the matrix: its number and the matrix values that make it.
struct SweepRun {
  int id{0};
  std::vector<Assignment> values;  ///< axis and combination values, in expansion order
  /// Ensemble member (run/ensemble.h): a case whose ensemble.members is N > 1 is N runs, member
  /// k adding EnsembleMemberSettings (its crank start, its settle) to the case's values.
  int member{0};
  int case_id{0};  ///< id of the case's member 0 (whose ideal-joint twin every member shares)
  /// "rod.material=steel, drive.speed=110 rpm"
  std::string Label() const;
};

/// A parsed, validated and expanded matrix.
struct SweepMatrix {
  std::string name;                    ///< [sweep] name, default: file stem
  std::string description;             ///< [sweep] description
  std::string origin;                  ///< where the matrix came from (file path or built-in name)
  std::string source;                  ///< the matrix text as given
  std::string base;                    ///< [sweep] base: preset name or TOML file
  std::string base_toml;               ///< the base input's text
  std::vector<Assignment> overrides;   ///< [set], then command-line --set, in order
  std::vector<std::string> axis_keys;  ///< every key that varies, in order of first appearance
  std::vector<SweepRun> runs;          ///< runs in id order (id = index)
  StoreOptions store;

  std::size_t num_runs() const { return runs.size(); }
  /// The run's complete input: base, overrides, then the run's values.
  Config ConfigFor(int id) const;
};

/// Parses a matrix. `base_dir` resolves a relative base file; `extra_sets` are "key=value"
/// overrides applied after [set] (command-line --set); "store.<option>=value" among them
/// overrides [store]. Throws InputError naming the key, the
/// value and the rule for: malformed TOML, an unknown section or [sweep]/[store] key, an
/// unknown input key, a value its key rejects, an empty axis or range, a zipped axis whose
/// rows do not match its keys, a key set by both [axes] and a combination or twice in one
/// place, two runs with the same resolved input, a missing base.
SweepMatrix ParseSweepMatrix(const std::string& toml_text, const std::string& origin,
                             const std::string& base_dir = ".",
                             const std::vector<std::string>& extra_sets = {});
/// A built-in matrix (a preset whose name starts with "sweep-") or a matrix file.
SweepMatrix LoadSweepMatrix(const std::string& name_or_path,
                            const std::vector<std::string>& extra_sets = {});
/// The matrix `flexrod sweep` runs without an argument: RIG.md Table 2.
inline constexpr const char* kDefaultSweepMatrix = "sweep-table2";

/// The complete matrix as JSON (base text included), to hand it to other MPI ranks.
nlohmann::json SweepMatrixToJson(const SweepMatrix& matrix);
SweepMatrix SweepMatrixFromJson(const nlohmann::json& json);

/// Store options from [store]-style key/value text ("channels", "rate", "spectrum_window",
/// "spectrum_max", "inflection_floor", "poincare_channels"); InputError("store.<key>", ...).
void SetStoreOption(StoreOptions* options, const std::string& key, const std::string& value);

/// Identity of a run's result: FNV-1a 64 of the resolved input (every key, SI, and whether it
/// was set) and the store options, as 16 hex digits. Equal fingerprints = equal results (runs
/// are deterministic).
std::string RunFingerprint(const Config& cfg, const StoreOptions& store);
/// Cache key of the run's reduced rod: the resolved rod.*, reduction.* and clamp.* values.
std::string RodKey(const Config& cfg);
/// 64-bit FNV-1a of a byte string as 16 lowercase hex digits.
std::string Fnv1aHex(const std::string& bytes);

}  // namespace flexrod::study
