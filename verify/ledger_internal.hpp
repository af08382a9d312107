/// What the three rooms of the ledger share (verify/ledger_load.cpp: reading and checking
/// suites/ledger.toml; ledger_evaluate.cpp: readings, checks and verdicts on a run;
/// ledger_page.cpp: ledger.md, ledger.csv): the value helpers and the case lookups. Private to
/// verify/; the interface is verify/ledger.hpp.
#pragma once
#include <string>
#include <vector>

#include "verify/ledger.hpp"
#include "verify/manifest.hpp"

namespace mfv::ledger_internal {

/// 5 significant digits (4 below 1e-2 or from 1e5), "–" for a value that is not finite.
std::string fmt_value(double v);
/// Values for people (5 digits), or for machines (`exact`: round-trip precision, empty for
/// a missing value).
std::string join_values(const std::vector<double>& v, bool exact = false);
/// A rate of a study under a statistic (least squares, finest pair, best pair).
double rate_value(const Rates& rates, const std::string& column, RateStatistic statistic);
/// One row's value of a measure in a study: a rate under the row's statistic, or a headline
/// at the finest resolution.
double measure_value(const StudyResult& s, const std::string& measure, RateStatistic statistic);
/// compare_value, with one-sided rows judged only on the side the claim excludes.
Comparison compare_row(double ours, double paper, const LedgerRow& row);
/// Per-value verdicts combined: all reproduced → reproduced, none even partly → not
/// reproduced, anything missing → not reached, otherwise partly.
std::string combine(const std::vector<Comparison>& cs);
/// "×0.92, +0.01": each value's gap as the row compares.
std::string gap_text(const LedgerEntry& e);
/// RFC 4180 quoting.
std::string csv_field(const std::string& s);
/// Whether resolved parameters contain every wanted one (as the problem pages match them).
bool params_match(const Params& resolved, const Params& wanted);
/// A published value belongs to a case's problem parameters when each of its own problem
/// parameters is the case's value or the case left it at its default.
bool problem_params_match(const Params& case_params, const Params& wanted);
/// The manifest's case of that id, or null.
const ManifestCase* find_case(const Manifest& m, const std::string& id);
/// A verdict from a comparison with the paper.
bool compared_verdict(const std::string& v);
/// Whether a measure is a rate (l2_rate, h1_rate, energy_rate).
bool is_rate_measure(const std::string& m);
/// A finding's uncertainty, one per number its verdict rests on (`o.numbers`), into
/// `o.uncertainty` and `o.uncertainty_of`: the GCI from the number's own levels, or against the
/// same number in the first converged check when it was read at one resolution.
void finding_uncertainty(LedgerReadingOutcome& o);

}  // namespace mfv::ledger_internal
