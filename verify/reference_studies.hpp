/// Studies computed by an independent implementation (issue 43): a route that shares no code
/// with mfv (tests/reference/*.py: numpy, written from the papers without reading mfv's
/// methods), recorded as JSON beside the script that writes it, and read back as StudyResults
/// so that a ledger row's finding is judged on them exactly as on our own run. The test
/// `reference/<name>` re-runs each script and fails when its output differs from the
/// recorded file, so a recorded number cannot drift from what the script computes.
///
/// File layout (schema "mfv-reference-1"):
///   { "schema": "mfv-reference-1", "generator": "tests/reference/kbm_cantilever_2d.py",
///     "problem": "cantilever", "problem_params": {},
///     "studies": [ { "label": "kbm-si (independent)", "method": "kbm-si",
///                    "method_params": {"dmax": 2.4},
///                    "cases": [ {"nodes": 5, "particles": 85, "h": 3.0,
///                                "l2_rel": 1e-2, "energy_rel": 5e-2, "h1_semi_rel": 4e-2}, … ] } ] }
/// l2_rel is required per case; energy_rel and h1_semi_rel may be null (not measured). Rates
/// are least-squares slopes of ln(error) against ln h, as our own (analyses/norms.hpp); the
/// absolute errors are not recorded, so a case's absolute fields hold the relative ones (the
/// same slopes).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "analyses/case.hpp"

namespace mfv {

inline constexpr const char* kReferenceSchema = "mfv-reference-1";

/// The studies of `file` whose label is one of `labels` (all of them when `labels` is
/// empty), in the file's order. InputError naming the file and the fix for a missing or
/// unreadable file, another schema, a study without cases, a case without l2_rel, or a label
/// the file does not hold.
std::vector<StudyResult> load_reference_studies(const std::filesystem::path& file,
                                                const std::vector<std::string>& labels = {});

}  // namespace mfv
