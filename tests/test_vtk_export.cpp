// VTK export: a short CPU run exported every 2nd frame, read back with VTK's own readers and
// compared with the simulation's state; bird selections; directories that cannot be written.
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "io/scenario_file.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/simulation.h"
#include "model/step.h"
#include "model/tail.h"
#include "output/vtk_export.h"
#include "test_files.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) { return testing::fresh_dir("vtk_" + name, false); }
using testing::read_text;

struct PvdEntry {
  double time;
  std::string file;
};

// The .pvd's DataSet entries, parsed as plain XML text (no ParaView reader in VTK itself).
std::vector<PvdEntry> read_pvd(const fs::path& path) {
  const std::string text = read_text(path);
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  std::vector<PvdEntry> entries;
  const std::regex dataset(R"re(<DataSet\s+timestep="([^"]+)"[^>]*\sfile="([^"]+)"\s*/>)re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset);
       it != std::sregex_iterator(); ++it)
    entries.push_back({std::stod((*it)[1].str()), (*it)[2].str()});
  return entries;
}

vtkSmartPointer<vtkPolyData> read_vtp(const fs::path& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), 0u) << path;
  vtkSmartPointer<vtkPolyData> data = reader->GetOutput();
  return data;
}

// The array `name` with `components` components, or a failed expectation and nullptr.
vtkDataArray* array(vtkPolyData* data, const char* name, int components) {
  vtkDataArray* a = data->GetPointData()->GetArray(name);
  EXPECT_NE(a, nullptr) << "no point array " << name;
  if (a) {
    EXPECT_EQ(a->GetNumberOfComponents(), components) << name;
    EXPECT_EQ(a->GetNumberOfTuples(), data->GetNumberOfPoints()) << name;
  }
  return a;
}

void expect_vec(vtkDataArray* a, vtkIdType i, const glm::dvec3& v, const char* what) {
  ASSERT_NE(a, nullptr);
  EXPECT_DOUBLE_EQ(a->GetComponent(i, 0), v.x) << what << " of point " << i;
  EXPECT_DOUBLE_EQ(a->GetComponent(i, 1), v.y) << what << " of point " << i;
  EXPECT_DOUBLE_EQ(a->GetComponent(i, 2), v.z) << what << " of point " << i;
}

struct Saved {
  double time;
  std::vector<BirdState> birds;
};

// A CPU run of fig21-moving-target with 5 birds for `frames` frames, exported as `options` says,
// from t = 0 as `aeroflock run` does (with `start`) or from the first due frame after it.
std::vector<Saved> run_and_export(const VtkOptions& options, uint32_t frames, Scenario* out,
                                  bool start = true) {
  Scenario scenario = load_scenario("fig21-moving-target");
  CpuSimulation sim(scenario, 5);
  VtkExporter exporter(options, sim.scenario(), sim.birds().size());
  std::vector<Saved> saved;
  if (start) {
    exporter.offer_start(sim);
    saved.push_back({0.0, sim.birds()});
  }
  for (uint32_t frame = 0; frame < frames; ++frame) {
    sim.step_frame(exporter.due(sim.frames() + 1));
    exporter.offer_ready(sim);
    if (exporter.due(sim.frames())) saved.push_back({sim.time(), sim.birds()});
  }
  exporter.finish();
  *out = sim.scenario();
  return saved;
}

// In double precision every value is the simulation's own, to the last bit.
TEST(VtkExport, FramesMatchTheSimulation) {
  VtkOptions options;
  options.dir = fresh_dir("frames");
  options.every = 2;
  options.precision = VtkOptions::Precision::float64;
  Scenario scenario;
  const std::vector<Saved> saved = run_and_export(options, 9, &scenario);
  ASSERT_EQ(saved.size(), 5u);  // the start, frames 2, 4, 6, 8

  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), saved.size());
  // Times are the step's, as written by a person: 0.06, not 0.059999999999999998.
  const std::string pvd_text = read_text(options.dir / "flock.pvd");
  for (const char* t : {"\"0\"", "\"0.06\"", "\"0.12\"", "\"0.18\"", "\"0.24\""})
    EXPECT_NE(pvd_text.find(std::string("timestep=") + t), std::string::npos) << t << " in\n"
                                                                              << pvd_text;
  for (size_t k = 0; k < pvd.size(); ++k) {
    SCOPED_TRACE("saved frame " + std::to_string(k));
    EXPECT_NEAR(pvd[k].time, saved[k].time, 1e-12);
    if (k > 0) {
      EXPECT_GT(pvd[k].time, pvd[k - 1].time);
    }
    const fs::path file = options.dir / pvd[k].file;
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_NE(read_text(file).find("compressor=\"vtkLZ4DataCompressor\""), std::string::npos);
    EXPECT_NE(read_text(file).find("header_type=\"UInt64\""), std::string::npos);

    vtkSmartPointer<vtkPolyData> data = read_vtp(file);
    const std::vector<BirdState>& birds = saved[k].birds;
    ASSERT_EQ(data->GetNumberOfPoints(), 5);
    EXPECT_EQ(data->GetNumberOfVerts(), 5);
    EXPECT_EQ(data->GetNumberOfCells(), 5);

    vtkDataArray* id = array(data, "bird_id", 1);
    vtkDataArray* species = array(data, "species", 1);
    vtkDataArray* time = array(data, "time", 1);
    vtkDataArray* velocity = array(data, "velocity", 3);
    vtkDataArray* speed = array(data, "speed", 1);
    vtkDataArray* attitude = array(data, "attitude", 4);
    vtkDataArray* hpb = array(data, "heading_pitch_bank", 3);
    vtkDataArray* phase = array(data, "wingbeat_phase", 1);
    vtkDataArray* frequency = array(data, "frequency", 1);
    vtkDataArray* amplitude = array(data, "amplitude", 1);
    vtkDataArray* bend = array(data, "tail_bend", 1);
    vtkDataArray* twist = array(data, "tail_twist", 1);
    vtkDataArray* opening = array(data, "tail_opening", 1);
    vtkDataArray* aero = array(data, "aero_force", 3);
    vtkDataArray* tail = array(data, "tail_force", 3);
    vtkDataArray* state = array(data, "flight_state", 1);
    vtkDataArray* target = array(data, "target", 1);
    ASSERT_FALSE(HasFailure());
    std::vector<std::string> written;
    for (int a = 0; a < data->GetPointData()->GetNumberOfArrays(); ++a)
      written.emplace_back(data->GetPointData()->GetArrayName(a));
    EXPECT_EQ(written, vtk_point_arrays());  // every array of the table, each once

    World world = scenario.world;
    world.move_targets(saved[k].time);
    for (vtkIdType i = 0; i < 5; ++i) {
      const BirdState& b = birds[static_cast<size_t>(i)];
      const Species& sp = scenario.species[b.species];
      double x[3];
      data->GetPoint(i, x);
      expect_vec(velocity, i, b.velocity, "velocity");
      EXPECT_EQ(glm::dvec3(x[0], x[1], x[2]), b.position) << "position of bird " << i;
      EXPECT_EQ(id->GetComponent(i, 0), double(i));
      EXPECT_EQ(species->GetComponent(i, 0), double(b.species));
      EXPECT_EQ(time->GetComponent(i, 0), pvd[k].time);
      EXPECT_DOUBLE_EQ(speed->GetComponent(i, 0), glm::length(b.velocity));
      EXPECT_EQ(attitude->GetComponent(i, 0), b.attitude.w);
      EXPECT_EQ(attitude->GetComponent(i, 1), b.attitude.x);
      EXPECT_EQ(attitude->GetComponent(i, 2), b.attitude.y);
      EXPECT_EQ(attitude->GetComponent(i, 3), b.attitude.z);
      const glm::dvec3 head = b.attitude * glm::dvec3{1.0, 0.0, 0.0};
      EXPECT_NEAR(hpb->GetComponent(i, 0), degrees(std::atan2(head.z, head.x)), 1e-9);
      EXPECT_NEAR(hpb->GetComponent(i, 1), degrees(pitch_angle(b.attitude)), 1e-9);
      EXPECT_NEAR(hpb->GetComponent(i, 2), degrees(bank_angle(b.attitude)), 1e-9);
      EXPECT_EQ(phase->GetComponent(i, 0), b.phase);
      EXPECT_EQ(frequency->GetComponent(i, 0), b.frequency);
      EXPECT_EQ(amplitude->GetComponent(i, 0), b.amplitude);
      EXPECT_DOUBLE_EQ(bend->GetComponent(i, 0), degrees(b.tail_bend));
      EXPECT_DOUBLE_EQ(twist->GetComponent(i, 0), degrees(b.tail_twist));
      ASSERT_EQ(b.mode, FlightMode::flying);
      EXPECT_DOUBLE_EQ(opening->GetComponent(i, 0),
                       degrees(tail_opening(sp, b.tail_bend, b.tail_twist)));
      EXPECT_EQ(state->GetComponent(i, 0), double(b.mode));
      EXPECT_EQ(target->GetComponent(i, 0), double(b.target));
      // The forces of the next step from this state, as step_bird gives them.
      BirdState copy = b;
      StepForces f;
      step_bird(copy, sp, world, saved[k].time, scenario.dt, &f);
      expect_vec(aero, i, f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3] + f.tail, "aero_force");
      expect_vec(tail, i, f.tail, "tail_force");
      EXPECT_GT(glm::length(f.tail), 0.0);
    }
  }

  // Trajectories: one polyline per bird, one point per saved frame, in time order.
  vtkSmartPointer<vtkPolyData> traj = read_vtp(options.dir / "trajectories.vtp");
  ASSERT_EQ(traj->GetNumberOfLines(), 5);
  EXPECT_EQ(traj->GetNumberOfPoints(), 5 * 5);
  vtkDataArray* traj_id = traj->GetCellData()->GetArray("bird_id");
  ASSERT_NE(traj_id, nullptr);
  vtkDataArray* traj_time = array(traj, "time", 1);
  vtkDataArray* traj_speed = array(traj, "speed", 1);
  ASSERT_FALSE(HasFailure());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < 5; ++c) {
    traj->GetLines()->GetCellAtId(c, ids);
    EXPECT_EQ(traj->GetCellType(c), VTK_POLY_LINE);
    EXPECT_EQ(traj_id->GetComponent(c, 0), double(c));
    ASSERT_EQ(ids->GetNumberOfIds(), 5);
    for (vtkIdType f = 0; f < 5; ++f) {
      const vtkIdType p = ids->GetId(f);
      const BirdState& b = saved[static_cast<size_t>(f)].birds[static_cast<size_t>(c)];
      double x[3];
      traj->GetPoint(p, x);
      EXPECT_EQ(glm::dvec3(x[0], x[1], x[2]), b.position);
      EXPECT_EQ(traj_time->GetComponent(p, 0), pvd[static_cast<size_t>(f)].time);
      EXPECT_DOUBLE_EQ(traj_speed->GetComponent(p, 0), glm::length(b.velocity));
    }
  }
  // No temporary files are left behind.
  for (const auto& e : fs::recursive_directory_iterator(options.dir))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

TEST(VtkExport, SelectedBirdsInTheOrderGiven) {
  VtkOptions options;
  options.dir = fresh_dir("selected");
  options.birds = "ids:4,1";
  options.compression = VtkOptions::Compression::zlib;
  Scenario scenario;
  const std::vector<Saved> saved = run_and_export(options, 3, &scenario);
  ASSERT_EQ(saved.size(), 4u);
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 4u);
  const fs::path last = options.dir / pvd.back().file;
  EXPECT_NE(read_text(last).find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  vtkSmartPointer<vtkPolyData> data = read_vtp(last);
  ASSERT_EQ(data->GetNumberOfPoints(), 2);
  vtkDataArray* id = array(data, "bird_id", 1);
  ASSERT_NE(id, nullptr);
  const uint32_t expected[2] = {4, 1};
  for (vtkIdType i = 0; i < 2; ++i) {
    EXPECT_EQ(id->GetComponent(i, 0), double(expected[i]));
    double x[3];
    data->GetPoint(i, x);
    EXPECT_EQ(glm::dvec3(x[0], x[1], x[2]), saved.back().birds[expected[i]].position);
  }
  vtkSmartPointer<vtkPolyData> traj = read_vtp(options.dir / "trajectories.vtp");
  EXPECT_EQ(traj->GetNumberOfLines(), 2);
  EXPECT_EQ(traj->GetNumberOfPoints(), 2 * 4);
}

// --vtk-from (VtkOptions::from): nothing before that frame, the start neither; then it and every
// `every`-th after it.
TEST(VtkExport, StartsAtTheFrameAskedAndKeepsItsStride) {
  VtkOptions options;
  options.dir = fresh_dir("from");
  options.from = 4;
  options.every = 3;
  Scenario scenario;
  const std::vector<Saved> saved = run_and_export(options, 12, &scenario, false);
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 3u);  // frames 4, 7 and 10
  ASSERT_EQ(saved.size(), 3u);
  const double frame = scenario.frame_seconds();
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(pvd[k].time, (4 + 3 * k) * frame, 1e-9) << k;
    EXPECT_NEAR(saved[k].time, pvd[k].time, 1e-9) << k;
  }
}

TEST(VtkExport, UncompressedAndASingleFrame) {
  VtkOptions options;
  options.dir = fresh_dir("single");
  options.every = 4;
  options.compression = VtkOptions::Compression::none;
  Scenario scenario;
  const std::vector<Saved> saved = run_and_export(options, 5, &scenario, /*start=*/false);
  ASSERT_EQ(saved.size(), 1u);
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 1u);
  const std::string text = read_text(options.dir / pvd[0].file);
  EXPECT_EQ(text.find("compressor="), std::string::npos);
  EXPECT_EQ(read_vtp(options.dir / pvd[0].file)->GetNumberOfPoints(), 5);
  // One saved position per bird is no line yet: one vertex per bird instead.
  vtkSmartPointer<vtkPolyData> traj = read_vtp(options.dir / "trajectories.vtp");
  EXPECT_EQ(traj->GetNumberOfPoints(), 5);
  EXPECT_EQ(traj->GetNumberOfCells(), 5);
  EXPECT_NE(traj->GetCellData()->GetArray("bird_id"), nullptr);
}

// Positions are Float64 in world coordinates, and the files say their length unit: a flock
// 1,000 km out reads back to the millimetre (to the last bit, in fact).
TEST(VtkExport, AFrameAThousandKilometresOutReadsBackToTheMillimetre) {
  VtkOptions options;
  options.dir = fresh_dir("far");
  const glm::dvec3 offset(1.0e8, 0.0, -3.0e7);
  const Scenario scenario = moved_by(load_scenario("fig21-moving-target"), offset);
  CpuSimulation sim(scenario, 5);
  for (int i = 0; i < 3; ++i) sim.step_frame();
  {
    VtkExporter exporter(options, sim.scenario(), sim.birds().size());
    sim.step_frame(true);
    exporter.offer(sim.snapshot());
    exporter.finish();
  }
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 1u);
  vtkSmartPointer<vtkPolyData> frame = read_vtp(options.dir / pvd[0].file);
  ASSERT_EQ(frame->GetNumberOfPoints(), 5);
  EXPECT_EQ(frame->GetPoints()->GetDataType(), VTK_DOUBLE);
  for (vtkIdType i = 0; i < 5; ++i) {
    double p[3];
    frame->GetPoint(i, p);
    const glm::dvec3 want = sim.birds()[size_t(i)].position;
    EXPECT_GT(want.x, 0.99e8);  // really out there
    EXPECT_LT(glm::length(glm::dvec3(p[0], p[1], p[2]) - want), 0.1) << "bird " << i;  // cm
  }
  vtkSmartPointer<vtkPolyData> trajectories = read_vtp(options.dir / "trajectories.vtp");
  for (vtkPolyData* data : {frame.Get(), trajectories.Get()}) {
    auto* unit =
        vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray("length_unit"));
    ASSERT_NE(unit, nullptr);
    EXPECT_EQ(unit->GetValue(0), "cm");
  }
}

// By default the point data's reals are Float32 (the device's own precision), the values the
// state's rounded to float; positions and times stay Float64.
TEST(VtkExport, FloatByDefaultPositionsAndTimesDouble) {
  VtkOptions options;
  options.dir = fresh_dir("float");
  Scenario scenario;
  const std::vector<Saved> saved = run_and_export(options, 2, &scenario);
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 3u);
  vtkSmartPointer<vtkPolyData> data = read_vtp(options.dir / pvd[2].file);
  EXPECT_EQ(data->GetPoints()->GetDataType(), VTK_DOUBLE);
  for (const std::string& name : vtk_point_arrays()) {
    vtkDataArray* a = data->GetPointData()->GetArray(name.c_str());
    ASSERT_NE(a, nullptr) << name;
    const int want =
        name == "time"      ? VTK_DOUBLE
        : name == "bird_id" ? VTK_UNSIGNED_INT
        : (name == "species" || name == "flight_state" || name == "target" || name == "neighbours")
            ? VTK_INT
            : VTK_FLOAT;
    EXPECT_EQ(a->GetDataType(), want) << name << " is " << a->GetDataTypeAsString();
  }
  const BirdState& b = saved[2].birds[3];
  double x[3];
  data->GetPoint(3, x);
  EXPECT_EQ(glm::dvec3(x[0], x[1], x[2]), b.position);
  EXPECT_EQ(data->GetPointData()->GetArray("velocity")->GetComponent(3, 0),
            double(float(b.velocity.x)));
  EXPECT_EQ(data->GetPointData()->GetArray("frequency")->GetComponent(3, 0),
            double(float(b.frequency)));
  EXPECT_EQ(data->GetPointData()->GetArray("time")->GetComponent(3, 0), 0.06);
}

// Every file says what it holds: the codes' names, every array's unit, the run, its time.
TEST(VtkExport, FilesDescribeThemselves) {
  VtkOptions options;
  options.dir = fresh_dir("described");
  Scenario scenario;
  run_and_export(options, 1, &scenario);
  const std::vector<PvdEntry> pvd = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(pvd.size(), 2u);
  auto strings = [](vtkPolyData* data, const char* name) {
    std::vector<std::string> values;
    auto* a = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
    EXPECT_NE(a, nullptr) << "no field data " << name;
    if (a)
      for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i) values.push_back(a->GetValue(i));
    return values;
  };
  vtkSmartPointer<vtkPolyData> frame = read_vtp(options.dir / pvd[1].file);
  vtkSmartPointer<vtkPolyData> trajectories = read_vtp(options.dir / "trajectories.vtp");
  for (vtkPolyData* data : {frame.Get(), trajectories.Get()}) {
    std::vector<std::string> names;
    for (const Species& sp : scenario.species) names.push_back(sp.name);
    EXPECT_EQ(strings(data, "species_names"), names);
    EXPECT_EQ(strings(data, "flight_state_names"),
              (std::vector<std::string>{"flying", "standing", "taking_off", "landing", "perched",
                                        "quarantined"}));
    EXPECT_EQ(strings(data, "scenario"), std::vector<std::string>{"fig21-moving-target"});
    EXPECT_EQ(strings(data, "scenario_hash"), std::vector<std::string>{scenario.hash});
    EXPECT_TRUE(scenario.hash.starts_with("fnv1a64:")) << scenario.hash;
    vtkDataArray* dt = data->GetFieldData()->GetArray("dt");
    ASSERT_NE(dt, nullptr);
    EXPECT_EQ(dt->GetComponent(0, 0), scenario.dt);
  }
  EXPECT_EQ(scenario.species[1].name, "starling");  // the code the frames carry
  EXPECT_EQ(frame->GetPointData()->GetArray("species")->GetComponent(0, 0), 1.0);
  vtkDataArray* time = frame->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_EQ(time->GetComponent(0, 0), 0.03);
  // Each point array once with its unit, the points' first.
  const std::vector<std::string> units = strings(frame, "array_units");
  ASSERT_EQ(units.size(), vtk_point_arrays().size() + 1);
  EXPECT_EQ(units[0].substr(0, 10), "points: cm");
  for (size_t i = 0; i < vtk_point_arrays().size(); ++i)
    EXPECT_EQ(units[i + 1].substr(0, vtk_point_arrays()[i].size() + 2),
              vtk_point_arrays()[i] + ": ");
  for (const char* expected :
       {"speed: cm/s", "aero_force: dyn", "heading_pitch_bank: deg", "time: s", "frequency: Hz"})
    EXPECT_NE(std::find(units.begin(), units.end(), expected), units.end()) << expected;
  EXPECT_NE(trajectories->GetCellData()->GetArray("species"), nullptr);
}

TEST(VtkExport, NoFramesStillWritesValidFiles) {
  VtkOptions options;
  options.dir = fresh_dir("empty");
  Scenario scenario = load_scenario("fig21-moving-target");
  { VtkExporter exporter(options, scenario, 1); }  // the destructor finishes
  ASSERT_TRUE(fs::exists(options.dir / "flock.pvd"));
  EXPECT_TRUE(read_pvd(options.dir / "flock.pvd").empty());
  ASSERT_TRUE(fs::exists(options.dir / "trajectories.vtp"));
  EXPECT_EQ(read_vtp(options.dir / "trajectories.vtp")->GetNumberOfPoints(), 0);
}

TEST(VtkExport, SelectBirds) {
  EXPECT_EQ(select_birds("all", 4), (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(select_birds("all", 0), std::vector<uint32_t>{});
  EXPECT_EQ(select_birds("every:3", 10), (std::vector<uint32_t>{0, 3, 6, 9}));
  EXPECT_EQ(select_birds("every:1", 3), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(select_birds("3,7,12", 13), (std::vector<uint32_t>{3, 7, 12}));
  EXPECT_EQ(select_birds("ids:3,7,12", 13), (std::vector<uint32_t>{3, 7, 12}));
  EXPECT_EQ(select_birds("ids:5", 6), (std::vector<uint32_t>{5}));
  EXPECT_EQ(select_birds(" 2, 0 ", 3), (std::vector<uint32_t>{2, 0}));

  auto rejects = [](const char* selection, size_t birds, const char* message) {
    try {
      select_birds(selection, birds);
      ADD_FAILURE() << selection << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos)
          << selection << ": " << e.what();
    }
  };
  rejects("", 10, "expected all, every:N or a list");
  rejects("some", 10, "expected all, every:N or a list");
  rejects("every:0", 10, "every:N needs N >= 1");
  rejects("every:", 10, "expected every:N");
  rejects("every:x", 10, "expected every:N");
  rejects("every:-2", 10, "expected every:N");
  rejects("3,,7", 10, "got ''");
  rejects("3,7,", 10, "got ''");
  rejects("ids:", 10, "expected all, every:N or a list");
  rejects("-1", 10, "got '-1'");
  rejects("1.5", 10, "got '1.5'");
  rejects("3,7,12", 12, "bird 12 is out of range (the flock has 12 birds: 0 to 11)");
  rejects("3,3", 12, "bird 3 is listed twice");
  rejects("99999999999999999999", 12, "expected a bird id");
}

TEST(VtkExport, UnwritableDirectoryFailsBeforeAnything) {
  const Scenario scenario = load_scenario("fig21-moving-target");
  VtkOptions options;
  options.dir = "/proc/aeroflock";
  try {
    VtkExporter exporter(options, scenario, 1);
    FAIL() << "no error for " << options.dir;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/aeroflock"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists("/proc/aeroflock"));

  // Below a regular file.
  const fs::path file = fresh_dir("file");
  std::ofstream(file) << "not a directory\n";
  options.dir = file / "vtk";
  EXPECT_THROW(VtkExporter(options, scenario, 1), std::runtime_error);
  fs::remove(file);

  // A bad selection is an error before anything is written, too.
  options.dir = fresh_dir("badselection");
  options.birds = "5";
  EXPECT_THROW(VtkExporter(options, scenario, 1), std::invalid_argument);
}

// The exported forces are the snapshot's, i.e. the backend's own (the shaders' on Vulkan): the
// exporter computes none. A due frame without forces is a programming error.
TEST(VtkExport, ForcesComeFromTheSnapshot) {
  Scenario scenario = load_scenario("fig21-moving-target");
  CpuSimulation sim(scenario, 2);
  VtkOptions options;
  options.dir = fresh_dir("forces");
  VtkExporter exporter(options, sim.scenario(), 2);
  sim.step_frame();
  EXPECT_THROW(exporter.offer(sim.snapshot()), std::logic_error);
  std::vector<StepForces> forces(2);
  forces[0].wing[0] = {1.0, 2.0, 3.0};
  forces[0].tail = {10.0, 20.0, 30.0};
  forces[1].tail = {-5.0, 0.0, 0.5};
  Snapshot snapshot = sim.snapshot();
  snapshot.forces = &forces;
  exporter.offer(snapshot);
  exporter.offer(snapshot);  // the same frame again: queued once
  exporter.finish();
  EXPECT_EQ(exporter.frames_added(), 1u);
  vtkSmartPointer<vtkPolyData> data = read_vtp(options.dir / "frames" / "flock_000000.vtp");
  expect_vec(array(data, "aero_force", 3), 0, {11.0, 22.0, 33.0}, "aero_force");
  expect_vec(array(data, "tail_force", 3), 1, {-5.0, 0.0, 0.5}, "tail_force");
}

TEST(VtkExport, WriterErrorIsReportedByFinish) {
  Scenario scenario = load_scenario("fig21-moving-target");
  CpuSimulation sim(scenario, 2);
  VtkOptions options;
  options.dir = fresh_dir("error");
  VtkExporter exporter(options, sim.scenario(), 2);
  sim.step_frame(true);
  exporter.offer(sim.snapshot());
  // The frames directory turns into a file: the next frame cannot be written.
  exporter.finish();
  options.overwrite = true;
  VtkExporter second(options, sim.scenario(), 2);
  fs::remove_all(options.dir / "frames");
  std::ofstream(options.dir / "frames") << "in the way\n";
  sim.step_frame(true);
  second.offer(sim.snapshot());
  sim.step_frame(true);
  second.offer(sim.snapshot());
  try {
    second.finish();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("flock_000000.vtp"), std::string::npos) << e.what();
    std::cout << "reported: " << e.what() << "\n";
  }
  EXPECT_TRUE(second.failed());
  second.finish();  // once reported, finishing again does nothing
}

// A slow disk slows the run instead of filling memory: offer() waits while queue_frames frames wait
// for the writer, and every frame is still written. Seen from outside: the frames offered less the
// frames the writer has begun never exceed the bound and the one it is writing.
TEST(VtkExport, ASlowDiskMakesTheRunWaitAndLosesNoFrame) {
  Scenario scenario = load_scenario("fig21-moving-target");
  scenario.steps_per_frame = 1;  // frames far faster than the disk
  CpuSimulation sim(scenario, 4);
  VtkOptions options;
  options.dir = fresh_dir("slow");
  options.queue_frames = 2;
  constexpr auto kDelay = std::chrono::milliseconds(40);
  std::atomic<int> begun{0};
  options.before_frame_write = [&] {
    ++begun;
    std::this_thread::sleep_for(kDelay);
  };
  VtkExporter exporter(options, sim.scenario(), 4);
  EXPECT_EQ(exporter.queue_bound(), 2u);
  constexpr int kFrames = 12;
  int most_ahead = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < kFrames; ++f) {
    sim.step_frame(true);
    exporter.offer(sim.snapshot());
    most_ahead = std::max(most_ahead, f + 1 - begun.load());
  }
  const auto offering = std::chrono::steady_clock::now() - start;
  exporter.finish();
  EXPECT_LE(most_ahead, 2 + 1) << "frames queued beyond the bound";
  EXPECT_GE(offering, (kFrames - 2 - 1) * kDelay) << "the run did not wait for the disk";
  // Its own count agrees (2 unless a busy machine let the writer keep up).
  EXPECT_LE(exporter.queue_high_water().frames, 2u);
  EXPECT_GE(exporter.queue_high_water().frames, 1u);
  EXPECT_EQ(exporter.frames_added(), size_t(kFrames));
  const std::vector<PvdEntry> entries = read_pvd(options.dir / "flock.pvd");
  ASSERT_EQ(entries.size(), size_t(kFrames));
  for (const PvdEntry& e : entries)
    EXPECT_EQ(read_vtp(options.dir / e.file)->GetNumberOfPoints(), 4);

  // The bound in bytes: one frame at a time when a frame is over it (an empty queue takes any).
  options.dir = fresh_dir("slow_bytes");
  options.queue_frames = 8;
  options.queue_bytes = 1;
  VtkExporter by_bytes(options, sim.scenario(), 4);
  for (int f = 0; f < 4; ++f) {
    sim.step_frame(true);
    by_bytes.offer(sim.snapshot());
  }
  by_bytes.finish();
  EXPECT_EQ(by_bytes.queue_high_water().frames, 1u);
  EXPECT_GT(by_bytes.queue_high_water().bytes, 4 * sizeof(BirdState));
  EXPECT_EQ(read_pvd(options.dir / "flock.pvd").size(), 4u);
}

// An earlier export in the directory: refused, or with overwrite its files (and no others)
// removed before the new one, which then lists only its own frames.
TEST(VtkExport, AnEarlierExportIsRefusedOrReplaced) {
  Scenario scenario = load_scenario("fig21-moving-target");
  CpuSimulation sim(scenario, 2);
  VtkOptions options;
  options.dir = fresh_dir("earlier");
  {
    VtkExporter first(options, sim.scenario(), 2);
    for (int f = 0; f < 3; ++f) {
      sim.step_frame(true);
      first.offer(sim.snapshot());
    }
  }
  EXPECT_EQ(earlier_export_files(options.dir).size(), 5u);  // .pvd, trajectories, 3 frames
  std::ofstream(options.dir / "frames" / "flock_1.vtp") << "mine\n";
  std::ofstream(options.dir / "frames" / "flock_000001.vtp.bak") << "mine\n";
  std::ofstream(options.dir / "notes.txt") << "mine\n";
  try {
    VtkExporter again(options, sim.scenario(), 2);
    FAIL() << "an earlier export was not refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "holds an earlier run's export (flock.pvd, trajectories.vtp, 3 frames)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_pvd(options.dir / "flock.pvd").size(), 3u);  // untouched
  options.overwrite = true;
  {
    VtkExporter replacing(options, sim.scenario(), 2);
    sim.step_frame(true);
    replacing.offer(sim.snapshot());
  }
  EXPECT_EQ(read_pvd(options.dir / "flock.pvd").size(), 1u);
  EXPECT_FALSE(fs::exists(options.dir / "frames" / "flock_000001.vtp"));
  for (const char* mine : {"frames/flock_1.vtp", "frames/flock_000001.vtp.bak", "notes.txt"})
    EXPECT_EQ(read_text(options.dir / mine), "mine\n") << mine;
}

}  // namespace
}  // namespace aeroflock
