// Unit tests of the column-keyed convergence table: rates, NaN handling, errors, order,
// Markdown and CSV, and bitwise agreement with verify's study_rates.
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "reports/convergence.hpp"
#include "reports/convergence_table.hpp"
#include "reports/markdown.hpp"
#include "analyses/case.hpp"
#include "analyses/norms.hpp"

using namespace mfv;

namespace {

const std::vector<double> kSpacings = {0.1, 0.05, 0.025, 0.0125};

/// Rows h, e_p = C h^p for the given orders, columns named "e<p>".
ConvergenceTable power_law_table(const std::vector<int>& orders, double c = 3.0) {
  ConvergenceTable t;
  for (double h : kSpacings) {
    t.add_row();
    t.add_value("h", h);
    for (int p : orders) t.add_value(fmt::format("e{}", p), c * std::pow(h, p));
  }
  return t;
}

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

/// The message of the std::invalid_argument `f` throws ("" if it throws nothing).
template <class F>
std::string invalid_argument_message(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ColumnConvergenceTable, PowerLawErrorsGiveTheirOrderAsFittedAndPairwiseRates) {
  const ConvergenceTable t = power_law_table({1, 2, 4});
  for (int p : {1, 2, 4}) {
    const std::string col = fmt::format("e{}", p);
    EXPECT_NEAR(t.rate(col), p, 1e-12) << col;
    const std::vector<double> r = t.pairwise(col);
    ASSERT_EQ(r.size(), kSpacings.size() - 1) << col;
    for (double x : r) EXPECT_NEAR(x, p, 1e-12) << col;
  }
  // The constant C drops out of every rate.
  EXPECT_NEAR(power_law_table({2}, 1e-7).rate("e2"), 2.0, 1e-12);
}

TEST(ColumnConvergenceTable, PairwiseRatesFollowEachPairOfRows) {
  // The error falls 4× (rate 2), then 2× (rate 1), then rises 2× (rate −1) on halved spacings.
  ConvergenceTable t;
  const std::vector<double> e = {1.0, 0.25, 0.125, 0.25};
  for (std::size_t i = 0; i < e.size(); ++i) t.add_row({{"h", kSpacings[i]}, {"L2", e[i]}});
  const std::vector<double> r = t.pairwise("L2");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_NEAR(r[1], 1.0, 1e-12);
  EXPECT_NEAR(r[2], -1.0, 1e-12);
  // The fit over all four rows lies between the extremes and is none of them.
  EXPECT_GT(t.rate("L2"), -1.0);
  EXPECT_LT(t.rate("L2"), 2.0);
  EXPECT_EQ(t.value(3, "L2"), 0.25);
  EXPECT_EQ(t.values("L2"), e);
}

TEST(ColumnConvergenceTable, FewerThanTwoRowsHaveNoRate) {
  ConvergenceTable t;
  t.add_row({{"h", 0.1}, {"L2", 0.01}});
  EXPECT_TRUE(std::isnan(t.rate("L2")));
  EXPECT_TRUE(t.pairwise("L2").empty());
}

TEST(ColumnConvergenceTable, ANanAnywhereInAColumnMakesItsFittedRateNan) {
  ConvergenceTable t = power_law_table({1, 2});
  ConvergenceTable u;
  for (std::size_t i = 0; i < kSpacings.size(); ++i)
    u.add_row({{"h", kSpacings[i]}, {"e2", i == 2 ? NAN : std::pow(kSpacings[i], 2)},
               {"e1", kSpacings[i]}});
  EXPECT_TRUE(std::isnan(u.rate("e2")));
  // The other column keeps its rate.
  EXPECT_NEAR(u.rate("e1"), 1.0, 1e-12);
  // Only the pairs touching the NaN row lose their pairwise rate.
  const std::vector<double> r = u.pairwise("e2");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(r[1]));
  EXPECT_TRUE(std::isnan(r[2]));
  EXPECT_FALSE(std::isnan(t.rate("e2")));
}

TEST(ColumnConvergenceTable, AValueNeverSetIsNanAndUndefinesTheRate) {
  ConvergenceTable t;
  t.add_row({{"h", 0.1}, {"L2", 0.01}});
  t.add_row({{"h", 0.05}, {"L2", 0.0025}, {"energy", 0.05}});  // energy from the second row on
  t.add_row({{"h", 0.025}, {"L2", 0.000625}});                 // and not in the third
  EXPECT_TRUE(std::isnan(t.value(0, "energy")));
  EXPECT_EQ(t.value(1, "energy"), 0.05);
  EXPECT_TRUE(std::isnan(t.value(2, "energy")));
  ASSERT_EQ(t.values("energy").size(), 3u);
  EXPECT_TRUE(std::isnan(t.rate("energy")));
  EXPECT_NEAR(t.rate("L2"), 2.0, 1e-12);
}

TEST(ColumnConvergenceTable, ZeroErrorsAreLeftOutOfTheFitAsVerifyDoes) {
  // run_study undefines a rate for NaN errors only; fitted_rate skips zeros (nothing measured).
  ConvergenceTable t;
  const std::vector<double> e = {0.01, 0.0, 0.000625, 0.00015625};
  for (std::size_t i = 0; i < e.size(); ++i) t.add_row({{"h", kSpacings[i]}, {"L2", e[i]}});
  EXPECT_EQ(bits(t.rate("L2")), bits(fitted_rate(kSpacings, e)));
  EXPECT_NEAR(t.rate("L2"), 2.0, 1e-12);
}

TEST(ColumnConvergenceTable, UnknownColumnsAreRefusedNamingTheKnownOnes) {
  ConvergenceTable t = power_law_table({1, 2});
  for (const std::string& msg :
       {invalid_argument_message([&] { t.rate("L3"); }),
        invalid_argument_message([&] { t.pairwise("L3"); }),
        invalid_argument_message([&] { t.value(0, "L3"); }),
        invalid_argument_message([&] { t.values("L3"); }),
        invalid_argument_message([&] { t.evaluate_rates("L3"); }),
        invalid_argument_message([&] { t.omit_from_rates("L3"); }),
        invalid_argument_message([&] { t.set_format("L3", [](double) { return ""; }); }),
        invalid_argument_message([&] { t.set_footer("L3", "x"); })}) {
    ASSERT_FALSE(msg.empty()) << "no std::invalid_argument";
    for (const char* name : {"\"L3\"", "\"h\"", "\"e1\"", "\"e2\""})
      EXPECT_NE(msg.find(name), std::string::npos) << name << " missing from: " << msg;
  }
  EXPECT_THROW(t.value(kSpacings.size(), "e1"), std::out_of_range);
}

TEST(ColumnConvergenceTable, TheAbscissaIsNotRatedAndMustExist) {
  ConvergenceTable t = power_law_table({2});
  EXPECT_NE(invalid_argument_message([&] { t.rate("h"); }).find("abscissa"), std::string::npos);
  ConvergenceTable no_h("dx");
  no_h.add_row({{"h", 0.1}, {"L2", 0.01}});
  no_h.add_row({{"h", 0.05}, {"L2", 0.0025}});
  const std::string msg = invalid_argument_message([&] { no_h.rate("L2"); });
  EXPECT_NE(msg.find("\"dx\""), std::string::npos) << msg;
  // Named otherwise, the abscissa works the same.
  ConvergenceTable dx("dx");
  dx.add_row({{"dx", 0.1}, {"L2", 0.01}});
  dx.add_row({{"dx", 0.05}, {"L2", 0.0025}});
  EXPECT_NEAR(dx.rate("L2"), 2.0, 1e-12);
}

TEST(ColumnConvergenceTable, RowsAreFilledOnceAndOnlyAfterAddRow) {
  ConvergenceTable t;
  EXPECT_THROW(t.add_value("h", 0.1), std::logic_error);
  t.add_row();
  t.add_value("h", 0.1);
  EXPECT_THROW(t.add_value("h", 0.2), std::logic_error);
  t.add_row();
  EXPECT_NO_THROW(t.add_value("h", 0.05));
  EXPECT_EQ(t.rows(), 2u);
}

TEST(ColumnConvergenceTable, ColumnsKeepTheirInsertionOrder) {
  ConvergenceTable t;
  t.add_row({{"nodes", 11}, {"h", 0.1}, {"L2", 0.01}, {"H1", 0.1}});
  t.add_row({{"nodes", 21}, {"h", 0.05}, {"H1", 0.05}, {"L2", 0.0025}, {"CPU", 0.5}});
  EXPECT_EQ(t.columns(), (std::vector<std::string>{"nodes", "h", "L2", "H1", "CPU"}));
  EXPECT_TRUE(t.has_column("CPU"));
  EXPECT_FALSE(t.has_column("cpu"));
  // Rates for every column but the abscissa and those omitted, in column order; each rate
  // column right after its own.
  t.omit_from_rates("nodes");
  t.omit_from_rates("CPU");
  t.evaluate_all_rates();
  EXPECT_EQ(t.rated_columns(), (std::vector<std::string>{"L2", "H1"}));
  EXPECT_EQ(t.header(),
            (std::vector<std::string>{"nodes", "h", "L2", "L2 rate", "H1", "H1 rate", "CPU"}));
  t.evaluate_rates("H1", "H1-semi rate [1]");
  EXPECT_EQ(t.header()[5], "H1-semi rate [1]");
  // A later evaluate_all_rates keeps the header chosen.
  t.evaluate_all_rates();
  EXPECT_EQ(t.header()[5], "H1-semi rate [1]");
  t.omit_from_rates("L2");
  EXPECT_EQ(t.rated_columns(), (std::vector<std::string>{"H1"}));
}

TEST(ColumnConvergenceTable, MarkdownShowsValuesPairwiseRatesAndTheLeastSquaresRow) {
  ConvergenceTable t("h [length]");
  for (int i = 0; i < 3; ++i) {
    const double h = kSpacings[i];
    t.add_row({{"nodes [1]", 10 << i}, {"h [length]", h}, {"L2 rel [1]", h * h},
               {"CPU [s]", 0.25}});
  }
  t.set_format("nodes [1]", [](double v) { return fmt::format("{:.0f}", v); });
  t.set_format("CPU [s]", [](double v) { return fmt::format("{:.3f}", v); });
  t.evaluate_rates("L2 rel [1]", "L2 rate [1]");
  t.set_footer("CPU [s]", "0.750");
  const std::string md = t.markdown();
  for (const char* h : {"nodes [1]", "h [length]", "L2 rel [1]", "L2 rate [1]", "CPU [s]"})
    EXPECT_NE(md.find(h), std::string::npos) << h << "\n" << md;
  // Row 2: 20 nodes, h 5e-2, L2 2.5e-3 with pairwise rate 2.00; the first row has no rate.
  EXPECT_TRUE(std::regex_search(md, std::regex(R"(\|\s+20 \|\s+5\.000e-02 \|\s+2\.500e-03 \|\s+2\.00 \|\s+0\.250 \|)")))
      << md;
  EXPECT_TRUE(std::regex_search(md, std::regex(R"(\|\s+10 \|\s+1\.000e-01 \|\s+1\.000e-02 \|\s+– \|)")))
      << md;
  // Last row: the label, the least-squares rate and the footer text.
  EXPECT_TRUE(std::regex_search(md, std::regex(R"(\| least squares \|\s+\|\s+\|\s+2\.00 \|\s+0\.750 \|\n$)")))
      << md;
  // Header, delimiter, three rows, the least-squares row.
  EXPECT_EQ(std::count(md.begin(), md.end(), '\n'), 6) << md;
  // A chosen rate format and footer label.
  t.set_rate_format([](double v) { return fmt::format("{:.4f}", v); });
  t.set_footer_label("fit");
  const std::string md4 = t.markdown();
  EXPECT_TRUE(std::regex_search(md4, std::regex(R"(\|\s+fit \|\s+\|\s+\|\s+2\.0000 \|)")))
      << md4;
  // NaN prints as "no value", never as a number.
  ConvergenceTable n;
  n.add_row({{"h", 0.1}, {"L2", NAN}});
  n.add_row({{"h", 0.05}, {"L2", 0.01}});
  n.evaluate_all_rates();
  EXPECT_EQ(n.cells()[0][1], "–");
  EXPECT_EQ(n.cells()[1][2], "–");
  EXPECT_EQ(n.footer()[2], "–");
}

TEST(ColumnConvergenceTable, MarkdownWithoutRatesHasNoFooterRow) {
  ConvergenceTable t = power_law_table({2});
  const std::string md = t.markdown();
  EXPECT_EQ(md.find("least squares"), std::string::npos) << md;
  EXPECT_EQ(std::count(md.begin(), md.end(), '\n'), 2 + static_cast<long>(kSpacings.size())) << md;
}

TEST(ColumnConvergenceTable, CsvHoldsEveryValueRoundTripAndThePairwiseRates) {
  ConvergenceTable t;
  const std::vector<double> e = {0.3, 0.1, NAN};
  for (std::size_t i = 0; i < e.size(); ++i)
    t.add_row({{"h", kSpacings[i]}, {"L2, rel", e[i]}, {"CPU", 0.125}});
  t.evaluate_rates("L2, rel");
  const std::vector<double> r = t.pairwise("L2, rel");
  const std::string expected =
      fmt::format("h,\"L2, rel\",\"L2, rel rate\",CPU\n"
                  "0.1,0.3,,0.125\n"
                  "0.05,0.1,{},0.125\n"
                  "0.025,nan,nan,0.125\n",
                  r[0]);
  EXPECT_EQ(t.csv(), expected);
  // Shortest round-trip: the rate reads back bit for bit (row 2, third field).
  const std::string csv = t.csv();
  const std::size_t row2 = csv.find("\n0.05,") + 1;
  std::size_t start = row2;
  for (int field = 0; field < 2; ++field) start = csv.find(',', start) + 1;
  const std::string rate_text = csv.substr(start, csv.find(',', start) - start);
  EXPECT_EQ(bits(std::stod(rate_text)), bits(r[0])) << rate_text;
}

TEST(ColumnConvergenceTable, TexIsABooktabsTabularWithEscapedTextAndTheFooter) {
  ConvergenceTable t;
  t.add_row({{"h", 0.1}, {"L2_rel & 100%", 0.4}});
  t.add_row({{"h", 0.05}, {"L2_rel & 100%", 0.1}});
  t.evaluate_rates("L2_rel & 100%");
  const std::string tex = t.tex();
  EXPECT_EQ(tex.rfind("\\begin{tabular}{rrr}\n\\toprule\n", 0), 0u) << tex;
  EXPECT_NE(tex.find("L2\\_rel \\& 100\\%"), std::string::npos) << tex;
  EXPECT_NE(tex.find("-- \\\\"), std::string::npos) << "the first row's rate: " << tex;
  EXPECT_NE(tex.find("\\midrule\nleast squares"), std::string::npos) << tex;
  EXPECT_NE(tex.find("2.00"), std::string::npos) << tex;
  EXPECT_TRUE(tex.ends_with("\\bottomrule\n\\end{tabular}\n")) << tex;
}

/// study_rates (analyses/norms.hpp) reads its rates off a table of the study's errors; they
/// must equal, bit for bit, the slopes fitted_rate and pairwise_rates give on the raw errors
/// (what the rates were before the table), so no baseline number moves.
TEST(ColumnConvergenceTable, StudyRatesEqualTheRawSlopesBitForBit) {
  // Hand-made cases with errors off any power law, so the summation order shows.
  const std::vector<double> h = {0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625};
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> wobble(0.5, 2.0);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 2 + trial % (h.size() - 1);
    std::vector<CaseResult> cases;
    std::vector<double> hs, l2, h1, en;
    for (std::size_t i = 0; i < n; ++i) {
      CaseResult c;
      c.h = h[i];
      c.errors.l2 = std::pow(h[i], 2) * wobble(rng);
      c.errors.h1_semi = h[i] * wobble(rng);
      c.errors.energy = std::pow(h[i], 1.5) * wobble(rng);
      if (trial % 7 == 3) c.errors.energy = i == 1 ? 0.0 : c.errors.energy;  // skipped by both
      cases.push_back(c);
      hs.push_back(c.h);
      l2.push_back(c.errors.l2);
      h1.push_back(c.errors.h1_semi);
      en.push_back(c.errors.energy);
    }
    const Rates r = study_rates(cases, false);
    SCOPED_TRACE(fmt::format("trial {} with {} resolutions", trial, n));
    EXPECT_EQ(bits(fitted_rate(hs, l2)), bits(r.rate(kRateL2)));
    EXPECT_EQ(bits(fitted_rate(hs, h1)), bits(r.rate(kRateH1Semi)));
    EXPECT_EQ(bits(fitted_rate(hs, en)), bits(r.rate(kRateEnergy)));
    auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
      if (a.size() != b.size()) return false;
      for (std::size_t i = 0; i < a.size(); ++i)
        if (bits(a[i]) != bits(b[i])) return false;
      return true;
    };
    EXPECT_TRUE(same(pairwise_rates(hs, l2), r.pairwise_of(kRateL2)));
    EXPECT_TRUE(same(pairwise_rates(hs, h1), r.pairwise_of(kRateH1Semi)));
    EXPECT_TRUE(same(pairwise_rates(hs, en), r.pairwise_of(kRateEnergy)));
  }
}

