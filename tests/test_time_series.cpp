/// Tests of the time-series writers (VTU + PVD, CSV histories, history plots) and the progress bar.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "temp_files.hpp"

#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "reports/plot.hpp"
#include "reports/progress.hpp"
#include "reports/time_series.hpp"
#include "analyses/case_vtk.hpp"
#include "analyses/report_section.hpp"
#include "reports/vtk.hpp"

namespace fs = std::filesystem;
using namespace mfv;

namespace {

using test::names_in;
using test::read_file;

/// A fresh directory per test (tests/temp_files.hpp).
class TempDir : public test::TempDir {
 public:
  TempDir() : test::TempDir("mfv-test-time-series") {}
};

/// Four particles in 2D with a scalar, a 2-vector and a Voigt stress, all distinct values.
ParticleFrame frame_2d(double t) {
  ParticleFrame f;
  f.time = t;
  f.x.resize(2, 4);
  f.x << 0.0, 1.0, 0.0, 1.0,  //
      0.0, 0.0, 1.0, 1.0;
  f.x.array() += t;  // moved, so frames differ
  Eigen::MatrixXd rho(1, 4), v(2, 4), s(3, 4);
  rho << 1.0, 1.1, 1.2, 1.3;
  v << 0.1, 0.2, 0.3, 0.4,  //
      -0.1, -0.2, -0.3, -0.4;
  s << 10, 11, 12, 13,  //
      20, 21, 22, 23,   //
      30, 31, 32, 33;
  f.point_data = {{"density", rho * (1 + t)}, {"velocity", v}, {"stress", s}};
  return f;
}

struct ReadBack {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkUnstructuredGrid* grid = nullptr;
  explicit ReadBack(const fs::path& p) {
    reader->SetFileName(p.c_str());
    reader->Update();
    grid = reader->GetOutput();
  }
};

/// Every timestep="..." attribute of a .pvd, in file order.
std::vector<double> pvd_times(const std::string& text) {
  std::vector<double> out;
  const std::string key = "timestep=\"";
  for (auto pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos + 1))
    out.push_back(std::stod(text.substr(pos + key.size())));
  return out;
}

}  // namespace

// ---------------------------------------------------------------- VTU series

TEST(VtuSeries, FramesReadBackWithPointsArraysAndValues) {
  TempDir dir;
  VtuSeriesWriter w(dir.path() / "series", "particles");  // creates the subdirectory
  w.write(frame_2d(0.0));
  w.write(frame_2d(0.5));
  w.finish();
  ASSERT_EQ(w.entries().size(), 2u);
  EXPECT_EQ(w.entries()[0].second, "particles_0000.vtu");
  EXPECT_EQ(w.entries()[1].second, "particles_0001.vtu");
  EXPECT_EQ(names_in(dir.path() / "series"),
            (std::vector<std::string>{"particles.pvd", "particles_0000.vtu",
                                      "particles_0001.vtu"}));

  const ParticleFrame expect = frame_2d(0.5);
  ReadBack rb(dir.path() / "series" / "particles_0001.vtu");
  vtkUnstructuredGrid* g = rb.grid;
  ASSERT_EQ(g->GetNumberOfPoints(), 4);
  ASSERT_EQ(g->GetNumberOfCells(), 4);
  for (vtkIdType i = 0; i < 4; ++i) {
    EXPECT_EQ(g->GetCellType(i), VTK_VERTEX);
    double p[3];
    g->GetPoint(i, p);
    EXPECT_DOUBLE_EQ(p[0], expect.x(0, i));
    EXPECT_DOUBLE_EQ(p[1], expect.x(1, i));
    EXPECT_EQ(p[2], 0.0);
  }
  vtkDataArray* rho = g->GetPointData()->GetArray("density");
  vtkDataArray* v = g->GetPointData()->GetArray("velocity");
  vtkDataArray* s = g->GetPointData()->GetArray("stress");
  ASSERT_NE(rho, nullptr);
  ASSERT_NE(v, nullptr);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(rho->GetNumberOfComponents(), 1);
  EXPECT_EQ(v->GetNumberOfComponents(), 3);  // padded so ParaView can warp by it
  // Voigt xx, yy, xy written as ParaView's symmetric tensor XX, YY, ZZ, XY, YZ, XZ.
  ASSERT_EQ(s->GetNumberOfComponents(), 6);
  const char* names[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c) EXPECT_STREQ(s->GetComponentName(c), names[c]) << c;
  for (vtkIdType i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(rho->GetComponent(i, 0), expect.point_data[0].second(0, i));
    EXPECT_DOUBLE_EQ(v->GetComponent(i, 0), expect.point_data[1].second(0, i));
    EXPECT_DOUBLE_EQ(v->GetComponent(i, 1), expect.point_data[1].second(1, i));
    EXPECT_EQ(v->GetComponent(i, 2), 0.0);
    const Eigen::MatrixXd& voigt = expect.point_data[2].second;
    EXPECT_DOUBLE_EQ(s->GetComponent(i, 0), voigt(0, i));
    EXPECT_DOUBLE_EQ(s->GetComponent(i, 1), voigt(1, i));
    EXPECT_DOUBLE_EQ(s->GetComponent(i, 3), voigt(2, i));
    for (int c : {2, 4, 5}) EXPECT_EQ(s->GetComponent(i, c), 0.0) << c;  // out of plane
  }
  vtkDataArray* time = g->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_DOUBLE_EQ(time->GetTuple1(0), 0.5);

  // The first frame holds its own values, not the last frame's.
  ReadBack first(dir.path() / "series" / "particles_0000.vtu");
  EXPECT_DOUBLE_EQ(first.grid->GetPoint(1)[0], 1.0);
  EXPECT_DOUBLE_EQ(first.grid->GetPointData()->GetArray("density")->GetComponent(3, 0), 1.3);
}

// The static 2D writers (reports/vtk.cpp) write the same tensor layout for the computed,
// exact and error stresses, at the particles and at the quadrature points.
TEST(VtkStress, StaticWritersWriteNamedSymmetricTensors) {
  TempDir dir;
  CaseResult r;
  r.h = 1;
  r.particles = 3;
  r.quadrature_kind = "nodal";
  CaseFields& f = r.data<StaticSolveData>().fields;
  f.points.resize(2, 3);
  f.points << 0, 1, 2,  //
      0, 0, 1;
  f.disp_h = f.disp_exact = Eigen::MatrixXd::Zero(2, 3);
  f.stress_h.resize(3, 3);
  f.stress_h << 1, 2, 3,  //
      4, 5, 6,            //
      7, 8, 9;
  f.stress_exact = Eigen::MatrixXd::Constant(3, 3, 0.5);
  f.volume = Eigen::VectorXd::Ones(3);
  f.q_points = f.points;
  f.q_stress_h = f.stress_h;
  f.q_stress_exact = f.stress_exact;
  const char* names[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (const char* file : {"particles.vtp", "quadrature.vtp"}) {
    const fs::path p = dir.path() / file;
    if (std::string(file) == "particles.vtp")
      write_particles_vtp(p, r);
    else
      write_quadrature_vtp(p, r);
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(p.c_str());
    reader->Update();
    vtkPolyData* pd = reader->GetOutput();
    ASSERT_EQ(pd->GetNumberOfPoints(), 3) << file;
    for (const char* array : {"stress", "stress_exact", "stress_error"}) {
      vtkDataArray* a = pd->GetPointData()->GetArray(array);
      ASSERT_NE(a, nullptr) << file << " " << array;
      ASSERT_EQ(a->GetNumberOfComponents(), 6) << file << " " << array;
      for (int c = 0; c < 6; ++c) EXPECT_STREQ(a->GetComponentName(c), names[c]) << array;
    }
    vtkDataArray* s = pd->GetPointData()->GetArray("stress");
    vtkDataArray* e = pd->GetPointData()->GetArray("stress_error");
    for (vtkIdType i = 0; i < 3; ++i) {
      EXPECT_EQ(s->GetComponent(i, 0), f.stress_h(0, i));  // XX
      EXPECT_EQ(s->GetComponent(i, 1), f.stress_h(1, i));  // YY
      EXPECT_EQ(s->GetComponent(i, 3), f.stress_h(2, i));  // XY
      for (int c : {2, 4, 5}) EXPECT_EQ(s->GetComponent(i, c), 0.0);
      EXPECT_EQ(e->GetComponent(i, 3), f.stress_h(2, i) - 0.5);
    }
  }
  EXPECT_THROW(stress_tensor(Eigen::MatrixXd::Zero(2, 3)), std::invalid_argument);
}

TEST(VtuSeries, OneDimensionalPositionsLieOnTheXAxis) {
  TempDir dir;
  VtuSeriesWriter w(dir.path(), "bar");
  ParticleFrame f;
  f.x.resize(1, 3);
  f.x << 0.0, 0.5, 1.0;
  Eigen::MatrixXd u(1, 3);
  u << 1e-3, 2e-3, 3e-3;
  f.point_data = {{"u", u}};
  w.write(f);
  ReadBack rb(dir.path() / "bar_0000.vtu");
  ASSERT_EQ(rb.grid->GetNumberOfPoints(), 3);
  double p[3];
  rb.grid->GetPoint(2, p);
  EXPECT_DOUBLE_EQ(p[0], 1.0);
  EXPECT_EQ(p[1], 0.0);
  EXPECT_EQ(p[2], 0.0);
  EXPECT_DOUBLE_EQ(rb.grid->GetPointData()->GetArray("u")->GetComponent(1, 0), 2e-3);
}

TEST(VtuSeries, PvdListsTimesInOrderWithRelativeFiles) {
  TempDir dir;
  VtuSeriesWriter w(dir.path(), "run");
  for (double t : {0.0, 0.25, 0.5, 1.0}) w.write(frame_2d(t));
  w.finish();
  const std::string text = read_file(dir.path() / "run.pvd");
  EXPECT_EQ(pvd_times(text), (std::vector<double>{0.0, 0.25, 0.5, 1.0}));
  for (int i = 0; i < 4; ++i) {
    const std::string file = "file=\"run_000" + std::to_string(i) + ".vtu\"";
    EXPECT_NE(text.find(file), std::string::npos) << file;
  }
  EXPECT_EQ(text.find(dir.path().string()), std::string::npos);  // relative names only
  // finish() again after another frame rewrites the list.
  w.write(frame_2d(2.0));
  w.finish();
  EXPECT_EQ(pvd_times(read_file(dir.path() / "run.pvd")),
            (std::vector<double>{0.0, 0.25, 0.5, 1.0, 2.0}));
}

TEST(VtuSeries, SameTimeReplacesEarlierTimeThrows) {
  TempDir dir;
  VtuSeriesWriter w(dir.path(), "run");
  w.write(frame_2d(0.0));
  w.write(frame_2d(1.0));
  ParticleFrame again = frame_2d(1.0);
  again.point_data[0].second(0, 0) = 42;
  w.write(again);
  ASSERT_EQ(w.entries().size(), 2u);
  EXPECT_EQ(w.entries()[1].second, "run_0001.vtu");
  ReadBack rb(dir.path() / "run_0001.vtu");
  EXPECT_DOUBLE_EQ(rb.grid->GetPointData()->GetArray("density")->GetComponent(0, 0), 42);
  try {
    w.write(frame_2d(0.5));
    FAIL() << "an earlier time was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("time order"), std::string::npos) << e.what();
  }
  EXPECT_EQ(w.entries().size(), 2u);
}

TEST(VtuSeries, MismatchedArrayThrowsNamingPathAndArrayAndWritesNothing) {
  TempDir dir;
  VtuSeriesWriter w(dir.path(), "run");
  ParticleFrame f = frame_2d(0.0);
  f.point_data[1].second.resize(2, 3);  // 3 columns for 4 particles
  try {
    w.write(f);
    FAIL() << "a 3-column array for 4 particles was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("run_0000.vtu"), std::string::npos) << what;
    EXPECT_NE(what.find("velocity"), std::string::npos) << what;
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
  EXPECT_TRUE(w.entries().empty());

  ParticleFrame four_rows = frame_2d(0.0);
  four_rows.point_data.push_back({"tensor", Eigen::MatrixXd::Zero(4, 4)});
  EXPECT_THROW(w.write(four_rows), std::invalid_argument);
  ParticleFrame twice = frame_2d(0.0);
  twice.point_data.push_back(twice.point_data[0]);
  EXPECT_THROW(w.write(twice), std::invalid_argument);
  ParticleFrame nan_time = frame_2d(0.0);
  nan_time.time = std::nan("");
  EXPECT_THROW(w.write(nan_time), std::invalid_argument);
  ParticleFrame no_x;
  EXPECT_THROW(w.write(no_x), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir.path()));
  EXPECT_THROW(VtuSeriesWriter(dir.path(), "a/b"), std::invalid_argument);
}

TEST(VtuSeries, DestructorListsFramesOfAnUnfinishedRun) {
  TempDir dir;
  {
    VtuSeriesWriter w(dir.path(), "crashed");
    w.write(frame_2d(0.0));
    w.write(frame_2d(0.1));
  }
  EXPECT_EQ(pvd_times(read_file(dir.path() / "crashed.pvd")),
            (std::vector<double>{0.0, 0.1}));
}

// ---------------------------------------------------------------- time histories

TEST(TimeHistory, AddChecksRowSize) {
  TimeHistory h{{"time", "kinetic", "internal"}, {}};
  h.add({0.0, 1.0, 2.0});
  EXPECT_THROW(h.add({0.1, 1.0}), std::invalid_argument);
  EXPECT_THROW(h.add({0.1, 1.0, 2.0, 3.0}), std::invalid_argument);
  EXPECT_EQ(h.rows.size(), 1u);
  TimeHistory empty;
  EXPECT_THROW(empty.add({1.0}), std::invalid_argument);
}

TEST(TimeHistory, ColumnReturnsValuesOrListsValidNames) {
  TimeHistory h{{"time", "kinetic", "internal"}, {}};
  h.add({0.0, 1.0, 2.0});
  h.add({0.5, 3.0, 4.0});
  EXPECT_EQ(h.column("internal"), (std::vector<double>{2.0, 4.0}));
  EXPECT_EQ(h.column("time"), (std::vector<double>{0.0, 0.5}));
  try {
    h.column("potential");
    FAIL() << "an unknown column was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("potential"), std::string::npos) << what;
    EXPECT_NE(what.find("time, kinetic, internal"), std::string::npos) << what;
  }
}

TEST(TimeHistory, CsvParsesBackToTheSameNumbers) {
  TempDir dir;
  TimeHistory h{{"time", "kinetic", "probe,vx"}, {}};
  const std::vector<std::vector<double>> rows = {
      {0.0, 1.0 / 3.0, -2.5e10}, {1e-7, 1e-300, 123456789.0}, {2e-7, -0.0, 6.02214076e23}};
  for (const auto& r : rows) h.add(r);
  const auto file = dir.path() / "energy.csv";
  write_history_csv(file, h);
  std::istringstream in(read_file(file));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time,kinetic,\"probe,vx\"");
  for (const auto& expect : rows) {
    ASSERT_TRUE(std::getline(in, line));
    std::istringstream fields(line);
    std::string field;
    for (double x : expect) {
      ASSERT_TRUE(std::getline(fields, field, ','));
      const double got = std::stod(field);
      EXPECT_NEAR(got, x, 1e-8 * std::abs(x)) << field;  // %.9g: 9 significant digits
    }
    EXPECT_FALSE(std::getline(fields, field, ',')) << "extra field in " << line;
  }
  EXPECT_FALSE(std::getline(in, line)) << "extra line " << line;
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"energy.csv"});

  h.rows.push_back({1.0});  // bypasses add()
  EXPECT_THROW(write_history_csv(dir.path() / "bad.csv", h), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.path() / "bad.csv"));
}

TEST(TimeHistory, PlotHasOneSeriesPerColumnAgainstTime) {
  TimeHistory h{{"time", "kinetic", "internal", "total"}, {}};
  for (int i = 0; i < 5; ++i) h.add({0.1 * i, 1.0 * i, 5.0 - i, 5.0});
  const PlotSpec p = history_plot(h, {"kinetic", "total"}, "Energy", "J");
  EXPECT_EQ(p.title, "Energy");
  EXPECT_EQ(p.ylabel, "J");
  EXPECT_EQ(p.xlabel, "time t (s)") << "the default axis names its unit";
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].label, "kinetic");
  EXPECT_EQ(p.series[1].label, "total");
  EXPECT_EQ(p.series[0].x, h.column("time"));
  EXPECT_EQ(p.series[0].y, h.column("kinetic"));
  EXPECT_EQ(history_plot(h, {}, "all", "J").series.size(), 3u);  // every non-time column
  EXPECT_THROW(history_plot(h, {"potential"}, "Energy", "J"), std::invalid_argument);
  EXPECT_EQ(history_plot(h, {}, "all", "J", "time t (ms)").xlabel, "time t (ms)");
  // A closed-form column is drawn as a reference, not as one more computed curve.
  TimeHistory probes{{"time", "v left end", "exact v left end", "u mid exact", "1D inner radius"},
                     {}};
  probes.add({0, 1, 1, 0, 2});
  const PlotSpec q = history_plot(probes, {}, "probes", "m/s");
  ASSERT_EQ(q.series.size(), 4u);
  EXPECT_EQ(q.series[0].role, SeriesRole::computed);
  EXPECT_EQ(q.series[1].role, SeriesRole::reference);
  EXPECT_EQ(q.series[2].role, SeriesRole::reference);
  EXPECT_EQ(q.series[3].role, SeriesRole::reference);
  EXPECT_FALSE(q.mark_off_scale) << "a run's probes are different quantities";
  if (gnuplot_available()) {
    TempDir dir;
    const auto svg = dir.path() / "energy.svg";
    EXPECT_EQ(write_svg_plot(svg, p), std::nullopt);
    EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
  }
}

// ---------------------------------------------------------------- progress bar

namespace {

/// A tmpfile, closed at the end, whose whole content can be read back.
class TempFile {
 public:
  TempFile() : f_(std::tmpfile()) {}
  ~TempFile() {
    if (f_) std::fclose(f_);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  std::FILE* get() const { return f_; }
  std::string content() const {
    std::fflush(f_);
    std::rewind(f_);
    std::string out;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f_)) > 0) out.append(buf, n);
    return out;
  }

 private:
  std::FILE* f_;
};

/// Sets or unsets an environment variable for one scope, restoring it afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

void run_steps(ProgressBar& bar, long n) {
  for (long s = 1; s <= n; ++s) bar.update(s, 1e-6 * s, "ms");
}

}  // namespace

TEST(ProgressBar, QuietWritesNothing) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  {
    ProgressBar bar("quiet", 100, /*quiet=*/true, f.get(), /*force=*/true);
    EXPECT_FALSE(bar.enabled());
    run_steps(bar, 100);
    bar.finish();
  }
  EXPECT_EQ(f.content(), "");
}

TEST(ProgressBar, NotATerminalWritesNothing) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  ASSERT_EQ(::isatty(::fileno(f.get())), 0);
  {
    ProgressBar bar("file", 100, /*quiet=*/false, f.get());
    EXPECT_FALSE(bar.enabled());
    run_steps(bar, 100);
  }  // the destructor's finish() must stay silent too
  EXPECT_EQ(f.content(), "");
}

TEST(ProgressBar, ForcedOutputShowsStepsAndEndsWithNewline) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  ProgressBar bar("explicit", 2500, /*quiet=*/false, f.get(), /*force=*/true);
  ASSERT_TRUE(bar.enabled());
  bar.update(1, 0.0, "ms");
  const std::string first = f.content();
  EXPECT_NE(first.find("step 1/2500"), std::string::npos) << first;  // first call draws at once
  EXPECT_NE(first.find("explicit ["), std::string::npos) << first;
  bar.update(1125, 0.0104, "ms");
  bar.finish();
  const std::string text = f.content();
  EXPECT_NE(text.find("step 1125/2500"), std::string::npos) << text;
  EXPECT_NE(text.find(" 45%"), std::string::npos) << text;
  EXPECT_NE(text.find("t=0.0104 ms"), std::string::npos) << text;
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  bar.finish();  // a second finish adds nothing
  EXPECT_EQ(f.content(), text);
}

TEST(ProgressBar, RedrawsAtMostAboutFiveTimesPerSecond) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  // Update as fast as possible for 1 s: unthrottled, that would be millions of lines.
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  long steps = 0;
  {
    ProgressBar bar("fast", 1L << 40, false, f.get(), true);
    while (Clock::now() - start < std::chrono::milliseconds(1000)) bar.update(++steps, 0.0);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const std::string text = f.content();
  const auto redraws = std::count(text.begin(), text.end(), '\r');
  // One draw at the first call, one at finish, and at most one per 200 ms in between.
  EXPECT_GE(redraws, 3) << text;  // ... but it does redraw while running
  EXPECT_LE(redraws, 3 + static_cast<long>(seconds * 5)) << seconds << " s, " << steps << " steps";
  EXPECT_NE(text.find("step " + std::to_string(steps) + "/"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
}

TEST(ProgressBar, ZeroTotalIsComplete) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  {
    ProgressBar bar("", 0, false, f.get(), true);
    bar.update(0, 0.0);
  }
  const std::string text = f.content();
  EXPECT_NE(text.find("100% step 0/0"), std::string::npos) << text;
  EXPECT_EQ(text.find(" ["), std::string::npos) << text;  // no label, no leading blank
}

TEST(ProgressBar, SlowStepsStillRedraw) {
  TempFile f;
  ASSERT_NE(f.get(), nullptr);
  ProgressBar bar("slow", 10, false, f.get(), true);
  for (long s = 1; s <= 4; ++s) {
    bar.update(s, 0.0);
    ::usleep(250'000);  // longer than the redraw interval
  }
  const std::string text = f.content();
  EXPECT_NE(text.find("step 3/10"), std::string::npos) << text;
  EXPECT_NE(text.find("ETA "), std::string::npos) << text;
}

TEST(ProgressBar, NegativeTotalThrows) {
  EXPECT_THROW(ProgressBar("bad", -1, true), std::invalid_argument);
}

TEST(ProgressBar, TerminalIsEnabledUnlessCiOrMfvQuiet) {
  // A pseudo-terminal stands in for an interactive stderr.
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    if (master >= 0) ::close(master);
    GTEST_SKIP() << "no pseudo-terminals here";
  }
  std::FILE* tty = std::fopen(::ptsname(master), "w");
  ASSERT_NE(tty, nullptr);
  ASSERT_EQ(::isatty(::fileno(tty)), 1);
  {
    ScopedEnv ci("CI", nullptr), quiet("MFV_QUIET", nullptr);
    ProgressBar bar("tty", 10, false, tty);
    EXPECT_TRUE(bar.enabled());
    bar.update(7, 0.0);
    bar.finish();
    pollfd p{master, POLLIN, 0};
    ASSERT_EQ(::poll(&p, 1, 2000), 1);
    char buf[512];
    const ssize_t n = ::read(master, buf, sizeof buf);
    ASSERT_GT(n, 0);
    EXPECT_NE(std::string(buf, static_cast<std::size_t>(n)).find("step 7/10"), std::string::npos);
    EXPECT_FALSE(ProgressBar("tty", 10, /*quiet=*/true, tty).enabled());
  }
  {
    ScopedEnv ci("CI", "true"), quiet("MFV_QUIET", nullptr);
    EXPECT_FALSE(ProgressBar("tty", 10, false, tty).enabled());
  }
  {
    ScopedEnv ci("CI", nullptr), quiet("MFV_QUIET", "1");
    EXPECT_FALSE(ProgressBar("tty", 10, false, tty).enabled());
  }
  std::fclose(tty);
  ::close(master);
}
