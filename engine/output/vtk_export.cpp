#include "output/vtk_export.h"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkType.h>
#include <vtkUnsignedIntArray.h>
#include <vtkXMLPolyDataWriter.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/paths.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/tail.h"
#include "model/world.h"

namespace aeroflock {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
// The trajectories are rewritten at most this often while the run goes on.
constexpr auto kTrajectoryInterval = std::chrono::seconds(2);

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// A whole non-negative decimal number, or throws naming `what`.
uint64_t parse_count(std::string_view text, std::string_view selection, const char* what) {
  const std::string_view t = trim(text);
  uint64_t value = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size())
    throw std::invalid_argument("bird selection '" + std::string(selection) + "': expected " +
                                what + ", got '" + std::string(t) + "'");
  return value;
}

// The shortest text that reads back as `value` ("0.03", not "0.029999999999999999").
std::string shortest(double value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  return std::string(text, ec == std::errc() ? end : text);
}

// The time after `steps` steps of `dt`, as the decimal a person would write: steps x dt rounded
// to 12 significant digits, so that 0.03 s is 0.03, not 0.029999999999999999 or
// 0.030000000000000002.
double step_time(uint64_t steps, double dt) {
  char text[32];
  std::snprintf(text, sizeof text, "%.12g", double(steps) * dt);
  return std::strtod(text, nullptr);
}

std::string frame_name(size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "flock_%06zu.vtp", index);
  return name;
}

// Over many ranks: frame `index`'s piece of rank `rank`, and the frame's collection of pieces.
std::string piece_name(size_t index, int rank) {
  char name[48];
  std::snprintf(name, sizeof name, "flock_%06zu_p%04d.vtp", index, rank);
  return name;
}
std::string pieces_name(size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "flock_%06zu.pvtp", index);
  return name;
}

bool all_digits(std::string_view digits, size_t least) {
  return digits.size() >= least &&
         std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Whether `name` is one that frame_name, piece_name or pieces_name gives: flock_ and six or more
// digits, .vtp; with _p and four or more digits before it; or .pvtp.
bool is_frame_name(std::string_view name) {
  if (!name.starts_with("flock_")) return false;
  name.remove_prefix(6);
  if (name.ends_with(".pvtp")) return all_digits(name.substr(0, name.size() - 5), 6);
  if (!name.ends_with(".vtp")) return false;
  name.remove_suffix(4);
  if (const size_t p = name.find("_p"); p != std::string_view::npos)
    return all_digits(name.substr(0, p), 6) && all_digits(name.substr(p + 2), 4);
  return all_digits(name, 6);
}

// vtkXMLPolyDataWriter onto a stream of ours: VTK 9.1 has no public setter for the stream it
// writes (vtkXMLWriter::Stream), and writing to its own file would leave the reason of a failure to
// its clean-up (it reads errno after removing the file).
class PolyDataStreamWriter : public vtkXMLPolyDataWriter {
 public:
  static PolyDataStreamWriter* New();
  vtkTypeMacro(PolyDataStreamWriter, vtkXMLPolyDataWriter)
      // For the next Write() (which rewinds it and forgets it at the end).
      void SetOutputStream(std::ostream* stream) {
    this->Stream = stream;
  }
};
vtkStandardNewMacro(PolyDataStreamWriter)

    // Writes `data` to `path` through an AtomicFile: the reason of a failure is the failing system
    // call's; VTK's own message only when no call failed.
    void write_polydata(vtkPolyData* data, const fs::path& path,
                        VtkOptions::Compression compression) {
  AtomicFile file(path);
  std::string message;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetClientData(&message);
  on_error->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    auto* text = static_cast<std::string*>(client);
    if (text->empty() && call) *text = static_cast<const char*>(call);
  });
  vtkNew<PolyDataStreamWriter> writer;
  writer->AddObserver(vtkCommand::ErrorEvent, on_error);
  writer->AddObserver(vtkCommand::WarningEvent, on_error);
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, on_error);
  writer->SetOutputStream(&file.stream());
  writer->SetInputData(data);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary, not base64
  writer->SetHeaderTypeToUInt64();  // blocks over 4 GiB: large flocks do not fail
  switch (compression) {
    case VtkOptions::Compression::none:
      writer->SetCompressorTypeToNone();
      break;
    case VtkOptions::Compression::lz4:
      writer->SetCompressorTypeToLZ4();
      break;
    case VtkOptions::Compression::zlib:
      writer->SetCompressorTypeToZLib();
      break;
  }
  const bool written = writer->Write() == 1 && writer->GetErrorCode() == 0;
  if (written || !file.error().empty()) {
    file.commit();  // throws the failing call's reason, if one failed
    return;
  }
  // VTK's messages start with the object ("vtkXMLPolyDataWriter (0x...): "): drop it.
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  if (const size_t nl = message.rfind('\n'); nl != std::string::npos) message.erase(0, nl + 1);
  if (const size_t colon = message.find("): ");
      message.starts_with("vtk") && colon != std::string::npos)
    message.erase(0, colon + 3);
  throw std::runtime_error(
      "cannot write " + path.string() + ": " +
      (message.empty() ? vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode()) : message));
}

template <typename Array>
vtkSmartPointer<Array> make_array(const char* name, int components, vtkIdType tuples) {
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

// One bird of a saved frame, as the point arrays see it.
struct ExportedBird {
  uint32_t id;
  double time;
  const BirdState& state;
  const Species& species;
  const StepForces& forces;
  const Perception& seen;  // its last perception (none when its flock does not flock)
  glm::dvec3 wind;         // the wind at its height
};

// What a point array holds: a real number (float or double as --vtk-precision says), a time
// (double always: it must name the step exactly), or an integer code or count.
enum class Value { real, time, integer, unsigned_integer };

// The point arrays of a frame file: name, kind, components, unit (in the file's array_units and
// docs/VTK.md "Arrays") and the bird's value. One line an array.
struct PointArray {
  const char* name;
  Value kind;
  int components;
  const char* unit;
  void (*value)(const ExportedBird& e, double* out);
};

void put(double* out, const glm::dvec3& v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

const PointArray kPointArrays[] = {
    {"bird_id", Value::unsigned_integer, 1, "-",
     [](const ExportedBird& e, double* v) { v[0] = e.id; }},
    {"species", Value::integer, 1, "- (code: species_names)",
     [](const ExportedBird& e, double* v) { v[0] = e.state.species; }},
    {"time", Value::time, 1, "s", [](const ExportedBird& e, double* v) { v[0] = e.time; }},
    {"velocity", Value::real, 3, "cm/s",
     [](const ExportedBird& e, double* v) { put(v, e.state.velocity); }},
    {"speed", Value::real, 1, "cm/s",
     [](const ExportedBird& e, double* v) { v[0] = glm::length(e.state.velocity); }},
    {"air_velocity", Value::real, 3, "cm/s",
     [](const ExportedBird& e, double* v) { put(v, e.state.velocity - e.wind); }},
    {"attitude", Value::real, 4, "- (unit quaternion w, x, y, z: body to world)",
     [](const ExportedBird& e, double* v) {
       const glm::dquat& q = e.state.attitude;
       v[0] = q.w, v[1] = q.x, v[2] = q.y, v[3] = q.z;
     }},
    {"heading_pitch_bank", Value::real, 3, "deg",
     [](const ExportedBird& e, double* v) {
       const glm::dvec3 head = e.state.attitude * glm::dvec3{1.0, 0.0, 0.0};
       put(v, {degrees(std::atan2(head.z, head.x)), degrees(pitch_angle(e.state.attitude)),
               degrees(bank_angle(e.state.attitude))});
     }},
    {"wingbeat_phase", Value::real, 1, "rad",
     [](const ExportedBird& e, double* v) { v[0] = e.state.phase; }},
    {"frequency", Value::real, 1, "Hz",
     [](const ExportedBird& e, double* v) { v[0] = e.state.frequency; }},
    {"amplitude", Value::real, 1, "- (factor of the wingbeat's joint angles)",
     [](const ExportedBird& e, double* v) { v[0] = e.state.amplitude; }},
    {"tail_bend", Value::real, 1, "deg",
     [](const ExportedBird& e, double* v) { v[0] = degrees(e.state.tail_bend); }},
    {"tail_twist", Value::real, 1, "deg",
     [](const ExportedBird& e, double* v) { v[0] = degrees(e.state.tail_twist); }},
    {"tail_opening", Value::real, 1, "deg",
     [](const ExportedBird& e, double* v) { v[0] = degrees(tail_opening(e.species, e.state)); }},
    {"aero_force", Value::real, 3, "dyn",
     [](const ExportedBird& e, double* v) {
       const StepForces& f = e.forces;
       put(v, f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3] + f.tail);
     }},
    {"tail_force", Value::real, 3, "dyn",
     [](const ExportedBird& e, double* v) { put(v, e.forces.tail); }},
    {"wingbeat_power", Value::real, 1, "erg/s (1e-7 W)",
     [](const ExportedBird& e, double* v) { v[0] = e.forces.power; }},
    {"wake_air", Value::real, 3, "cm/s",
     [](const ExportedBird& e, double* v) { put(v, e.forces.wake_air); }},
    {"flight_state", Value::integer, 1, "- (code: flight_state_names)",
     [](const ExportedBird& e, double* v) { v[0] = double(e.state.mode); }},
    {"target", Value::integer, 1, "- (index into the bird's route)",
     [](const ExportedBird& e, double* v) { v[0] = e.state.target; }},
    {"neighbours", Value::integer, 1, "-",
     [](const ExportedBird& e, double* v) { v[0] = e.seen.neighbours; }},
    {"nearest_neighbour", Value::real, 1, "cm",
     [](const ExportedBird& e, double* v) { v[0] = e.seen.nearest; }},
    {"social_direction", Value::real, 3, "- (unit vector, world)",
     [](const ExportedBird& e, double* v) { put(v, e.seen.direction); }},
};

int vtk_type(Value kind, VtkOptions::Precision precision) {
  switch (kind) {
    case Value::real:
      return precision == VtkOptions::Precision::float32 ? VTK_FLOAT : VTK_DOUBLE;
    case Value::time:
      return VTK_DOUBLE;
    case Value::integer:
      return VTK_INT;
    case Value::unsigned_integer:
      return VTK_UNSIGNED_INT;
  }
  return VTK_DOUBLE;
}

// The flight states' names, by code (flight_mode.def).
std::vector<std::string> flight_state_names() {
  std::vector<std::string> names;
  auto put_name = [&names](const char* name, uint32_t code) {
    if (names.size() <= code) names.resize(code + 1);
    names[code] = name;
  };
#define AF_FLIGHT_MODE(name, value) put_name(#name, value);
#define AF_LANDING_STAGE(name, value)
#include "model/flight_mode.def"
#undef AF_FLIGHT_MODE
#undef AF_LANDING_STAGE
  return names;
}

vtkSmartPointer<vtkStringArray> string_array(const char* name,
                                             const std::vector<std::string>& values) {
  auto a = vtkSmartPointer<vtkStringArray>::New();
  a->SetName(name);
  for (const std::string& v : values) a->InsertNextValue(v);
  return a;
}

// A numeric array of VTK type `type` (VTK_FLOAT, ...), sized.
vtkSmartPointer<vtkDataArray> data_array(const char* name, int type, int components,
                                         vtkIdType tuples) {
  auto a = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(type));
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

template <typename Array, typename T>
vtkSmartPointer<Array> value_array(const char* name, T value) {
  auto a = make_array<Array>(name, 1, 1);
  a->SetValue(0, value);
  return a;
}

}  // namespace

std::vector<std::string> vtk_point_arrays() {
  std::vector<std::string> names;
  for (const PointArray& a : kPointArrays) names.emplace_back(a.name);
  return names;
}

std::vector<uint32_t> select_birds(std::string_view selection, size_t bird_count) {
  const std::string_view s = trim(selection);
  std::vector<uint32_t> ids;
  if (s == "all") {
    ids.resize(bird_count);
    for (size_t i = 0; i < bird_count; ++i) ids[i] = static_cast<uint32_t>(i);
    return ids;
  }
  if (s.starts_with("every:")) {
    const uint64_t n = parse_count(s.substr(6), selection, "every:N with N >= 1");
    if (n == 0)
      throw std::invalid_argument("bird selection '" + std::string(selection) +
                                  "': every:N needs N >= 1");
    for (uint64_t i = 0; i < bird_count; i += n) ids.push_back(static_cast<uint32_t>(i));
    return ids;
  }
  std::string_view list = s;
  if (list.starts_with("ids:")) list.remove_prefix(4);
  if (trim(list).empty())
    throw std::invalid_argument("bird selection '" + std::string(selection) +
                                "': expected all, every:N or a list of bird ids like 3,7,12");
  std::vector<bool> seen(bird_count, false);
  while (true) {
    const size_t comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    if (trim(item).empty() || !std::isdigit(static_cast<unsigned char>(trim(item).front())))
      throw std::invalid_argument(
          "bird selection '" + std::string(selection) +
          "': expected all, every:N or a list of bird ids like 3,7,12, got '" +
          std::string(trim(item)) + "'");
    const uint64_t id = parse_count(item, selection, "a bird id");
    if (id >= bird_count)
      throw std::invalid_argument("bird selection '" + std::string(selection) + "': bird " +
                                  std::to_string(id) + " is out of range (the flock has " +
                                  std::to_string(bird_count) +
                                  (bird_count == 1 ? " bird: 0 to " : " birds: 0 to ") +
                                  std::to_string(bird_count == 0 ? 0 : bird_count - 1) + ")");
    if (seen[id])
      throw std::invalid_argument("bird selection '" + std::string(selection) + "': bird " +
                                  std::to_string(id) + " is listed twice");
    seen[id] = true;
    ids.push_back(static_cast<uint32_t>(id));
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return ids;
}

// The name of a VTK data type in an XML file's header.
const char* xml_type(int type) {
  switch (type) {
    case VTK_FLOAT:
      return "Float32";
    case VTK_INT:
      return "Int32";
    case VTK_UNSIGNED_INT:
      return "UInt32";
    default:
      return "Float64";
  }
}

struct VtkExporter::Writer {
  struct Frame {
    double time = 0.0;
    std::vector<uint32_t> ids;           // pieces: their global ids (else Writer::ids)
    std::vector<BirdState> birds;        // the selected birds, in the order of `ids`
    std::vector<StepForces> forces;      // theirs, of the next step
    std::vector<Perception> perception;  // theirs, as last perceived
    size_t bytes() const {
      return birds.size() * sizeof(BirdState) + forces.size() * sizeof(StepForces) +
             perception.size() * sizeof(Perception);
    }
  };

  // Fixed at construction.
  fs::path dir;
  VtkOptions::Compression compression;
  VtkOptions::Precision precision;
  std::vector<uint32_t> ids;
  std::vector<uint32_t> id_species;  // the species of each exported bird, by position in ids
  std::vector<Species> species;
  World world;  // its wind
  std::string scenario_name, scenario_hash;
  std::vector<std::string> species_names, state_names;  // by code
  std::vector<std::string> frame_units;                 // "name: unit" of each point array
  double dt = 0.0;
  uint32_t steps_per_frame = 0;
  std::function<void()> before_frame_write;
  // Over many ranks: this rank, of how many.
  bool pieces = false;
  int rank = 0, ranks = 1;

  // The writer thread's own: the jobs below run there, one at a time.
  std::vector<std::pair<double, std::string>> collection;  // time, file relative to dir
  std::vector<double> saved_times;
  std::vector<glm::dvec3> saved_positions;  // frame-major: frame * ids.size() + bird
  std::vector<double> saved_speeds;
  bool trajectories_stale = false;
  Clock::time_point trajectories_written{};  // long ago: the first frame writes them at once
  // Pieces: this rank's written whole (read by the run's thread), their times, its birds'
  // saved positions for rank 0's trajectories.
  std::atomic<uint64_t> pieces_written{0};
  std::vector<double> piece_times;
  std::vector<TrajectoryPoint> saved_points;

  // After each frame, and every kTrajectoryInterval without one: the trajectories, when stale.
  void trajectories_if_due() {
    if (trajectories_stale && Clock::now() - trajectories_written >= kTrajectoryInterval)
      write_trajectories();
  }
  // After the last frame (also after an error: the frames written until then), the final
  // collection, even empty, and the trajectories.
  void close() {
    std::exception_ptr first;
    try {
      write_collection();
    } catch (...) {
      first = std::current_exception();
    }
    try {
      if (trajectories_stale || trajectories_written == Clock::time_point{}) write_trajectories();
    } catch (...) {
      if (!first) first = std::current_exception();
    }
    if (first) std::rethrow_exception(first);
  }

  // Field data that makes a file describe itself: the run (scenario, its hash, dt), the names
  // of the codes, and the unit of the points and of every array ("name: unit").
  void add_field_data(vtkPolyData* data, const std::vector<std::string>& units) const {
    vtkFieldData* fd = data->GetFieldData();
    std::vector<std::string> all_units{"points: cm (world frame, y up)"};
    all_units.insert(all_units.end(), units.begin(), units.end());
    fd->AddArray(string_array("array_units", all_units));
    fd->AddArray(string_array("length_unit", {"cm"}));
    fd->AddArray(string_array("species_names", species_names));
    fd->AddArray(string_array("flight_state_names", state_names));
    fd->AddArray(string_array("scenario", {scenario_name}));
    fd->AddArray(string_array("scenario_hash", {scenario_hash}));
    fd->AddArray(value_array<vtkDoubleArray>("dt", dt));
    fd->AddArray(value_array<vtkIntArray>("steps_per_frame", int(steps_per_frame)));
  }

  void write_frame(const Frame& frame) {
    const vtkIdType n = static_cast<vtkIdType>(frame.birds.size());
    const std::vector<uint32_t>& frame_ids = pieces ? frame.ids : ids;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(n);
    std::vector<vtkSmartPointer<vtkDataArray>> arrays;
    for (const PointArray& a : kPointArrays)
      arrays.push_back(data_array(a.name, vtk_type(a.kind, precision), a.components, n));
    auto rank_array = make_array<vtkIntArray>("rank", 1, n);
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfTuples(n + 1);
    connectivity->SetNumberOfTuples(n);
    std::vector<glm::dvec3> positions(static_cast<size_t>(n));
    std::vector<double> speeds(static_cast<size_t>(n));

    double value[4];
    if (id_species.empty() && !pieces)
      for (const BirdState& b : frame.birds) id_species.push_back(b.species);
    for (vtkIdType i = 0; i < n; ++i) {
      const size_t k = static_cast<size_t>(i);
      const BirdState& b = frame.birds[k];
      const ExportedBird e{frame_ids[k],
                           frame.time,
                           b,
                           species[b.species],
                           frame.forces[k],
                           frame.perception[k],
                           wind_at(world, b.position.y)};
      rank_array->SetValue(i, rank);
      points->SetPoint(i, b.position.x, b.position.y, b.position.z);
      for (size_t a = 0; a < std::size(kPointArrays); ++a) {
        kPointArrays[a].value(e, value);
        arrays[a]->SetTuple(i, value);
      }
      offsets->SetValue(i, i);
      connectivity->SetValue(i, i);
      positions[k] = b.position;
      speeds[k] = glm::length(b.velocity);
    }
    offsets->SetValue(n, n);

    vtkNew<vtkCellArray> verts;
    verts->SetData(offsets, connectivity);
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    data->SetVerts(verts);
    vtkPointData* pd = data->GetPointData();
    for (const auto& a : arrays) pd->AddArray(a);
    pd->SetActiveVectors("velocity");
    std::vector<std::string> units = frame_units;
    if (pieces) {
      pd->AddArray(rank_array);
      units.push_back("rank: - (the MPI rank that owned the bird)");
    }
    add_field_data(data, units);
    // ParaView reads a frame's time from TimeValue, also when the file is opened alone.
    data->GetFieldData()->AddArray(value_array<vtkDoubleArray>("TimeValue", frame.time));
    if (pieces) {
      data->GetFieldData()->AddArray(value_array<vtkIntArray>("ranks", ranks));
      const uint64_t index = pieces_written.load();
      if (before_frame_write) before_frame_write();
      write_polydata(data, dir / "frames" / piece_name(index, rank), compression);
      piece_times.push_back(frame.time);
      for (size_t k = 0; k < positions.size(); ++k)
        saved_points.push_back(
            {frame_ids[k], frame.birds[k].species, index, positions[k], speeds[k]});
      pieces_written.store(index + 1);
      return;
    }

    const std::string name = "frames/" + frame_name(collection.size());
    if (before_frame_write) before_frame_write();
    write_polydata(data, dir / name, compression);
    // Only frames written in full, and listed in the .pvd, reach the collection and the
    // trajectories.
    list(frame.time, name);
    saved_times.push_back(frame.time);
    saved_positions.insert(saved_positions.end(), positions.begin(), positions.end());
    saved_speeds.insert(saved_speeds.end(), speeds.begin(), speeds.end());
    trajectories_stale = true;
  }

  // Pieces, rank 0: frames [listed, complete), every rank's piece of them written, each a .pvtp
  // of the pieces, listed in the .pvd.
  void list_pieces(uint64_t complete) {
    for (uint64_t k = collection.size(); k < complete; ++k) {
      std::string text =
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"PPolyData\" version=\"0.1\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n"
          "  <PPolyData GhostLevel=\"0\">\n"
          "    <PPointData Vectors=\"velocity\">\n";
      for (const PointArray& a : kPointArrays)
        text += std::string("      <PDataArray type=\"") + xml_type(vtk_type(a.kind, precision)) +
                "\" Name=\"" + a.name + "\" NumberOfComponents=\"" + std::to_string(a.components) +
                "\"/>\n";
      text +=
          "      <PDataArray type=\"Int32\" Name=\"rank\" NumberOfComponents=\"1\"/>\n"
          "    </PPointData>\n"
          "    <PPoints>\n"
          "      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n"
          "    </PPoints>\n";
      for (int r = 0; r < ranks; ++r) text += "    <Piece Source=\"" + piece_name(k, r) + "\"/>\n";
      text += "  </PPolyData>\n</VTKFile>\n";
      const std::string name = "frames/" + pieces_name(k);
      write_text_atomically(dir / name, text);
      list(piece_times[k], name);
    }
  }

  // The frame file `name` (relative to dir), written, listed in the .pvd at `time`; a frame the
  // .pvd cannot list is removed again.
  void list(double time, const std::string& name) {
    collection.emplace_back(time, name);
    try {
      write_collection();
    } catch (...) {
      collection.pop_back();
      std::error_code ignored;
      fs::remove(dir / name, ignored);
      throw;
    }
  }

  // Pieces, rank 0: the trajectories of every rank's points of the frames [0, complete).
  void write_piece_trajectories(const std::vector<TrajectoryPoint>& all, uint64_t complete) {
    saved_times.assign(piece_times.begin(), piece_times.begin() + std::ptrdiff_t(complete));
    saved_positions.assign(ids.size() * complete, glm::dvec3{0.0});
    saved_speeds.assign(ids.size() * complete, 0.0);
    id_species.assign(ids.size(), 0);
    std::vector<int64_t> slot(ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end()) + 1, -1);
    for (size_t b = 0; b < ids.size(); ++b) slot[ids[b]] = int64_t(b);
    for (const TrajectoryPoint& p : all) {
      if (p.frame >= complete || p.id >= slot.size() || slot[p.id] < 0) continue;
      const size_t b = size_t(slot[p.id]);
      saved_positions[p.frame * ids.size() + b] = p.position;
      saved_speeds[p.frame * ids.size() + b] = p.speed;
      id_species[b] = p.species;
    }
    write_trajectories();
  }

  // flock.pvd: every frame file written so far with its time.
  void write_collection() {
    std::string text =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <Collection>\n";
    for (const auto& [t, file] : collection)
      text += "    <DataSet timestep=\"" + shortest(t) + "\" group=\"\" part=\"0\" file=\"" + file +
              "\"/>\n";
    text += "  </Collection>\n</VTKFile>\n";
    write_text_atomically(dir / "flock.pvd", text);
  }

  // trajectories.vtp: one polyline per bird through its saved positions (a single saved frame:
  // one vertex per bird, a polyline needing two points).
  void write_trajectories() {
    const size_t birds = ids.size();
    const size_t frames = saved_times.size();
    const vtkIdType n = static_cast<vtkIdType>(birds * frames);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(n);
    auto time = make_array<vtkDoubleArray>("time", 1, n);
    auto speed = data_array("speed", vtk_type(Value::real, precision), 1, n);
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    const vtkIdType cells = frames > 0 ? static_cast<vtkIdType>(birds) : 0;
    offsets->SetNumberOfTuples(cells + 1);
    offsets->SetValue(0, 0);
    connectivity->SetNumberOfTuples(n);
    auto bird_id = make_array<vtkUnsignedIntArray>("bird_id", 1, cells);
    auto bird_species = make_array<vtkIntArray>("species", 1, cells);
    for (size_t b = 0; b < birds && frames > 0; ++b) {
      for (size_t f = 0; f < frames; ++f) {
        const vtkIdType p = static_cast<vtkIdType>(b * frames + f);
        const glm::dvec3& x = saved_positions[f * birds + b];
        points->SetPoint(p, x.x, x.y, x.z);
        time->SetValue(p, saved_times[f]);
        speed->SetTuple1(p, saved_speeds[f * birds + b]);
        connectivity->SetValue(p, p);
      }
      offsets->SetValue(static_cast<vtkIdType>(b + 1), static_cast<vtkIdType>((b + 1) * frames));
      bird_id->SetValue(static_cast<vtkIdType>(b), ids[b]);
      bird_species->SetValue(static_cast<vtkIdType>(b), int(id_species[b]));
    }
    vtkNew<vtkCellArray> cell_array;
    cell_array->SetData(offsets, connectivity);
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    if (frames >= 2)
      data->SetLines(cell_array);
    else
      data->SetVerts(cell_array);
    data->GetPointData()->AddArray(time);
    data->GetPointData()->AddArray(speed);
    data->GetCellData()->AddArray(bird_id);
    data->GetCellData()->AddArray(bird_species);
    add_field_data(data, {"time: s", "speed: cm/s", "bird_id: - (cell data)",
                          "species: - (cell data; code: species_names)"});
    write_polydata(data, dir / "trajectories.vtp", compression);
    trajectories_stale = false;
    trajectories_written = Clock::now();
  }
};

VtkExporter::VtkExporter(const VtkOptions& options, const Scenario& scenario, size_t bird_count)
    : dir_(options.dir), every_(options.every), from_(options.from), bird_count_(bird_count) {
  if (options.every == 0) throw std::invalid_argument("VTK export: every must be >= 1");
  selected_ = select_birds(options.birds, bird_count);
  if (dir_.empty()) throw std::invalid_argument("VTK export: no directory given");
  if (options.ranks && options.ranks->ranks > 1) {
    ranks_ = options.ranks;
    chosen_.assign(bird_count, false);
    for (uint32_t id : selected_) chosen_[id] = true;
  }
  if (!ranks_ || ranks_->rank == 0) prepare_dir(options);
  start_writer(options, scenario);
}

void VtkExporter::prepare_dir(const VtkOptions& options) {
  // Create and probe the directories before the run (which removes a killed run's temporaries).
  check_writable_dir(dir_, "VTK export directory");
  check_writable_dir(dir_ / "frames", "VTK export directory");
  // An earlier export: its frames would stay beside this run's, its .pvd list them until the first
  // is written. Refused, or removed (its own files only) when asked.
  if (const std::vector<fs::path> earlier = earlier_export_files(dir_); !earlier.empty()) {
    if (!options.overwrite) {
      size_t frames = 0;
      for (const fs::path& f : earlier) frames += f.parent_path().filename() == "frames";
      std::string what;
      for (const char* name : {"flock.pvd", "trajectories.vtp"})
        if (std::find(earlier.begin(), earlier.end(), dir_ / name) != earlier.end())
          what += std::string(what.empty() ? "" : ", ") + name;
      if (frames > 0)
        what += (what.empty() ? "" : ", ") + std::to_string(frames) + " frame" +
                (frames == 1 ? "" : "s");
      throw std::runtime_error("VTK export directory " + dir_.string() +
                               " holds an earlier run's export (" + what +
                               "): --overwrite replaces it, or choose another directory");
    }
    for (const fs::path& f : earlier) {
      std::error_code ec;
      fs::remove(f, ec);
      if (ec)
        throw std::runtime_error("VTK export directory " + dir_.string() + ": cannot remove " +
                                 f.string() + " of an earlier run: " + ec.message());
    }
  }
}

void VtkExporter::start_writer(const VtkOptions& options, const Scenario& scenario) {
  writer_ = std::make_unique<Writer>();
  Writer& w = *writer_;
  w.dir = dir_;
  if (ranks_) {
    w.pieces = true;
    w.rank = ranks_->rank;
    w.ranks = ranks_->ranks;
  }
  w.compression = options.compression;
  w.precision = options.precision;
  w.ids = selected_;
  w.species = scenario.species;
  w.world = scenario.world;
  w.scenario_name = scenario.name;
  w.scenario_hash = scenario.hash;
  for (const Species& sp : scenario.species) w.species_names.push_back(sp.name);
  w.state_names = flight_state_names();
  for (const PointArray& a : kPointArrays)
    w.frame_units.push_back(std::string(a.name) + ": " + a.unit);
  w.dt = scenario.dt;
  w.steps_per_frame = scenario.steps_per_frame;
  w.before_frame_write = options.before_frame_write;
  async_ = std::make_unique<AsyncWriter>(
      AsyncWriter::Limits{options.queue_frames, options.queue_bytes},
      [&w] { w.trajectories_if_due(); },
      std::chrono::milliseconds(500));  // the trajectories at most about 2.5 s behind
}

VtkExporter::~VtkExporter() {
  try {
    // Over many ranks finish() is collective, and a destructor may run on one rank alone (an
    // error unwinding it): the writer only stops then.
    if (ranks_ && !finished_) {
      finished_ = true;
      async_->finish();
    } else {
      finish();
    }
  } catch (...) {
    // Reported by finish() when the caller asks; a destructor must not throw.
  }
}

void VtkExporter::offer(const Snapshot& snapshot, bool due_or_not) {
  if (finished_) throw std::logic_error("VtkExporter::offer after finish()");
  if (!(due_or_not ? !any_offered_ || snapshot.frame > last_frame_ : wants(snapshot.frame))) return;
  const std::vector<BirdState>& birds = *snapshot.birds;
  if (!ranks_ && birds.size() != bird_count_)
    throw std::invalid_argument("VtkExporter::offer: expected " + std::to_string(bird_count_) +
                                " birds, got " + std::to_string(birds.size()));
  if (!snapshot.forces)
    throw std::logic_error("VtkExporter::offer: frame " + std::to_string(snapshot.frame) +
                           " is due but was not stepped with record_forces");
  last_frame_ = snapshot.frame;
  any_offered_ = true;
  if (async_->failed()) return;
  Writer::Frame frame;
  frame.time = step_time(snapshot.steps, writer_->dt);
  frame.birds.reserve(selected_.size());
  frame.forces.reserve(selected_.size());
  frame.perception.reserve(selected_.size());
  auto take = [&](size_t k) {
    frame.birds.push_back(birds[k]);
    frame.forces.push_back((*snapshot.forces)[k]);
    frame.perception.push_back(snapshot.perception ? (*snapshot.perception)[k] : Perception{});
  };
  if (ranks_) {
    // This rank's birds that are chosen, by their global ids.
    for (size_t k = 0; k < birds.size(); ++k) {
      const uint32_t id = snapshot.ids ? (*snapshot.ids)[k] : uint32_t(k);
      if (id < chosen_.size() && chosen_[id]) frame.ids.push_back(id), take(k);
    }
  } else {
    for (uint32_t id : selected_) take(id);
  }
  const size_t bytes = frame.bytes();
  Writer& w = *writer_;
  async_->push(bytes, [&w, frame = std::move(frame)] { w.write_frame(frame); });
  ++frames_added_;
}

bool VtkExporter::failed() const { return async_->failed(); }

VtkExporter::QueueUse VtkExporter::queue_high_water() const {
  const AsyncWriter::Use use = async_->high_water();
  return {use.jobs, use.bytes};
}

size_t VtkExporter::queue_bound() const { return async_->job_bound(); }

std::vector<fs::path> earlier_export_files(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const char* name : {"flock.pvd", "trajectories.vtp"})
    if (fs::is_regular_file(dir / name, ec)) files.push_back(dir / name);
  for (fs::directory_iterator it(dir / "frames", ec), end; !ec && it != end; it.increment(ec))
    if (std::error_code ignored;
        is_frame_name(it->path().filename().string()) && it->is_regular_file(ignored))
      files.push_back(it->path());
  std::sort(files.begin(), files.end());
  return files;
}

void VtkExporter::announce_pieces() {
  const uint64_t complete = ranks_->fewest(writer_->pieces_written.load());
  if (ranks_->rank != 0 || complete <= announced_) return;
  announced_ = complete;
  Writer& w = *writer_;
  async_->push(0, [&w, complete] { w.list_pieces(complete); });
}

void VtkExporter::finish() {
  if (finished_) return;
  finished_ = true;
  Writer& w = *writer_;
  if (!ranks_) {
    async_->finish([&w] { w.close(); });
    return;
  }
  // Over many ranks every rank goes through the collectives below, whatever its writer did.
  std::exception_ptr first;
  try {
    async_->finish();
  } catch (...) {
    first = std::current_exception();
  }
  const uint64_t complete = ranks_->fewest(w.pieces_written.load());
  std::vector<TrajectoryPoint> mine;
  for (const TrajectoryPoint& p : w.saved_points)
    if (p.frame < complete) mine.push_back(p);
  const std::vector<TrajectoryPoint> all = ranks_->gather(mine);
  if (ranks_->rank != 0) {
    if (first) std::rethrow_exception(first);
    return;
  }
  try {
    w.list_pieces(complete);
    w.write_collection();
    w.write_piece_trajectories(all, complete);
  } catch (...) {
    if (!first) first = std::current_exception();
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace aeroflock
