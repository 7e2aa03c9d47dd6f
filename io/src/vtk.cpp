#include "strata/io/vtk.hpp"

#include "atomic_file.hpp"
#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "vtk_grid.hpp"

#if STRATA_WITH_VTK
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkLongLongArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cmath>
#include <numeric>
#include <string>
#endif

namespace strata::io {

#if STRATA_WITH_VTK
namespace {

template <typename VtkArray, typename T>
vtkSmartPointer<vtkDataArray> fill(const Array& a, const std::vector<std::size_t>* pick) {
  auto out = vtkSmartPointer<VtkArray>::New();
  out->SetName(a.name.c_str());
  out->SetNumberOfComponents(a.components);
  const std::size_t n = pick ? pick->size() : a.tuples();
  out->SetNumberOfTuples(static_cast<vtkIdType>(n));
  T* dst = out->GetPointer(0);
  const auto comps = static_cast<std::size_t>(a.components);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t src = pick ? (*pick)[i] : i;
    for (std::size_t c = 0; c < comps; ++c) {
      const double v = a.values[src * comps + c];
      if constexpr (std::is_integral_v<T>)
        dst[i * comps + c] = static_cast<T>(std::llround(v));
      else
        dst[i * comps + c] = static_cast<T>(v);
    }
  }
  return out;
}

/// A VTK array holding `a` (only the tuples in `pick`, when given).
vtkSmartPointer<vtkDataArray> to_vtk(const Array& a, const std::vector<std::size_t>* pick = nullptr) {
  switch (a.type) {
    case ArrayType::Float64:
      return fill<vtkDoubleArray, double>(a, pick);
    case ArrayType::Float32:
      return fill<vtkFloatArray, float>(a, pick);
    case ArrayType::Int64:
      return fill<vtkLongLongArray, long long>(a, pick);
    case ArrayType::Int32:
      return fill<vtkIntArray, int>(a, pick);
    case ArrayType::UInt8:
      return fill<vtkUnsignedCharArray, unsigned char>(a, pick);
  }
  fail(ErrorKind::Internal, "unknown ArrayType for array '{}'", a.name);
}

Array from_vtk(vtkDataArray* d) {
  Array a;
  a.name = d->GetName() ? d->GetName() : "";
  a.components = d->GetNumberOfComponents();
  switch (d->GetDataType()) {
    case VTK_FLOAT:
      a.type = ArrayType::Float32;
      break;
    case VTK_UNSIGNED_CHAR:
      a.type = ArrayType::UInt8;
      break;
    case VTK_INT:
    case VTK_SHORT:
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
    case VTK_UNSIGNED_SHORT:
      a.type = ArrayType::Int32;
      break;
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_UNSIGNED_INT:
    case VTK_UNSIGNED_LONG:
    case VTK_UNSIGNED_LONG_LONG:
    case VTK_ID_TYPE:
      a.type = ArrayType::Int64;
      break;
    default:
      a.type = ArrayType::Float64;
  }
  const vtkIdType n = d->GetNumberOfTuples();
  a.values.resize(static_cast<std::size_t>(n) * a.components);
  for (vtkIdType i = 0; i < n; ++i)
    for (int c = 0; c < a.components; ++c) a.values[i * a.components + c] = d->GetComponent(i, c);
  return a;
}

vtkSmartPointer<vtkPoints> make_points(const PointCloud& cloud, const std::vector<std::size_t>* pick) {
  auto pts = vtkSmartPointer<vtkPoints>::New();
  pts->SetDataTypeToDouble();
  const std::size_t n = pick ? pick->size() : cloud.size();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t s = pick ? (*pick)[i] : i;
    pts->SetPoint(static_cast<vtkIdType>(i), cloud.xyz[3 * s], cloud.xyz[3 * s + 1], cloud.xyz[3 * s + 2]);
  }
  return pts;
}

/// Field data "dimension", "TimeValue" (ParaView reads it) and "step".
template <typename Frame>
void add_field_data(vtkDataObject* data, const Frame& frame) {
  vtkNew<vtkIntArray> dim;
  dim->SetName("dimension");
  dim->InsertNextValue(frame.dim);
  data->GetFieldData()->AddArray(dim);
  if (frame.time) {
    vtkNew<vtkDoubleArray> t;
    t->SetName("TimeValue");
    t->InsertNextValue(*frame.time);
    data->GetFieldData()->AddArray(t);
  }
  if (frame.step) {
    vtkNew<vtkLongLongArray> s;
    s->SetName("step");
    s->InsertNextValue(*frame.step);
    data->GetFieldData()->AddArray(s);
  }
}

/// Reads the field data written by add_field_data (dimension defaults to 3).
template <typename Frame>
void read_field_data(vtkDataObject* data, Frame& frame) {
  frame.dim = 3;
  auto* fd = data->GetFieldData();
  if (!fd) return;
  if (auto* d = fd->GetArray("dimension"); d && d->GetNumberOfTuples() > 0)
    frame.dim = static_cast<int>(d->GetComponent(0, 0));
  if (auto* d = fd->GetArray("TimeValue"); d && d->GetNumberOfTuples() > 0)
    frame.time = d->GetComponent(0, 0);
  if (auto* d = fd->GetArray("step"); d && d->GetNumberOfTuples() > 0)
    frame.step = static_cast<std::int64_t>(d->GetComponent(0, 0));
}

/// Writes `data` with an XML writer through `<path>.tmp` and a rename, with explicit
/// format settings.
template <typename Writer>
void write_xml(const std::filesystem::path& path, vtkDataObject* data) {
  detail::make_parent(path);
  const auto tmp = detail::temp_path(path);
  vtkNew<Writer> w;
  w->SetInputData(data);
  w->SetFileName(tmp.c_str());
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();  // raw binary, as ParaView writes it
  w->SetCompressorTypeToZLib();
  w->SetHeaderTypeToUInt64();
  w->SetIdTypeToInt64();
  const int ok = w->Write();
  if (!ok || w->GetErrorCode() != 0) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    fail(ErrorKind::IO, "VTK could not write {} (error code {})", tmp.string(),
         static_cast<int>(w->GetErrorCode()));
  }
  detail::commit(tmp, path);
}

}  // namespace

void write_particles(const std::filesystem::path& path, const PointCloud& particles) {
  validate(particles);
  STRATA_CHECK(particles.find(kRadiusArray), Input, "write_particles({}): the point cloud has no '{}' array",
               path.string(), kRadiusArray);
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(make_points(particles, nullptr));
  // One vertex cell per point, built directly as offsets + connectivity.
  const auto n = static_cast<vtkIdType>(particles.size());
  vtkNew<vtkIdTypeArray> offsets, conn;
  offsets->SetNumberOfValues(n + 1);
  conn->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) {
    offsets->SetValue(i, i);
    conn->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, conn);
  pd->SetVerts(verts);
  for (const auto& a : particles.point_data) pd->GetPointData()->AddArray(to_vtk(a));
  add_field_data(pd, particles);
  write_xml<vtkXMLPolyDataWriter>(path, pd);
}

void write_lines(const std::filesystem::path& path, const PointCloud& points, const LineSet& lines) {
  validate(points, &lines);
  // Keep only the points some line uses, in their original order.
  std::vector<std::int64_t> new_index(points.size(), -1);
  for (auto e : lines.ends) new_index[e] = 0;
  std::vector<std::size_t> pick;
  for (std::size_t i = 0; i < new_index.size(); ++i)
    if (new_index[i] == 0) {
      new_index[i] = static_cast<std::int64_t>(pick.size());
      pick.push_back(i);
    }
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(make_points(points, &pick));
  const auto m = static_cast<vtkIdType>(lines.size());
  vtkNew<vtkIdTypeArray> offsets, conn;
  offsets->SetNumberOfValues(m + 1);
  conn->SetNumberOfValues(2 * m);
  for (vtkIdType i = 0; i < m; ++i) {
    offsets->SetValue(i, 2 * i);
    conn->SetValue(2 * i, new_index[lines.ends[2 * i]]);
    conn->SetValue(2 * i + 1, new_index[lines.ends[2 * i + 1]]);
  }
  offsets->SetValue(m, 2 * m);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);
  pd->SetLines(cells);
  for (const auto& a : points.point_data) pd->GetPointData()->AddArray(to_vtk(a, &pick));
  for (const auto& a : lines.cell_data) pd->GetCellData()->AddArray(to_vtk(a));
  add_field_data(pd, points);
  write_xml<vtkXMLPolyDataWriter>(path, pd);
}

namespace {
/// Keeps the first error a VTK object reports in the std::string `client`: VTK's XML readers
/// print the errors of a truncated or damaged file and go on with what they could read, so
/// read_checked() collects them and turns them into an Error.
void keep_first_error(vtkObject*, unsigned long, void* client, void* message) {
  auto& first = *static_cast<std::string*>(client);
  if (first.empty()) first = message ? static_cast<const char*>(message) : "an error without a message";
}

/// Reads `path` with the XML reader `r`; throws Error(IO) naming the file and VTK's first
/// complaint when the file is damaged.
void read_checked(vtkXMLReader* r, const std::filesystem::path& path) {
  std::string why;
  vtkNew<vtkCallbackCommand> errors;
  errors->SetCallback(keep_first_error);
  errors->SetClientData(&why);
  r->SetReaderErrorObserver(errors);
  r->SetParserErrorObserver(errors);
  const unsigned long tag = r->AddObserver(vtkCommand::ErrorEvent, errors);
  r->SetFileName(path.c_str());
  r->Update();
  // `why` ends with this call: the reader must not report into it afterwards
  r->SetReaderErrorObserver(nullptr);
  r->SetParserErrorObserver(nullptr);
  r->RemoveObserver(tag);
  if (why.empty() && (r->GetErrorCode() != 0 || !r->GetOutputDataObject(0))) why = "VTK could not read it";
  // VTK's messages read "ERROR: In <source>, line <n>\n<class> (<address>): <what>\n": keep <what>.
  if (const auto at = why.find("): "); at != std::string::npos) why = why.substr(at + 3);
  while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
  for (char& c : why)
    if (c == '\n') c = ' ';
  STRATA_CHECK(why.empty(), IO, "{} is damaged or not a VTK XML file of its kind: {}", path.string(), why);
}
}  // namespace

VtpContents read_vtp(const std::filesystem::path& path) {
  STRATA_CHECK(std::filesystem::exists(path), IO, "cannot read {}: no such file", path.string());
  vtkNew<vtkXMLPolyDataReader> r;
  read_checked(r, path);
  vtkPolyData* pd = r->GetOutput();
  VtpContents out;
  auto& cloud = out.points;
  const vtkIdType n = pd->GetNumberOfPoints();
  cloud.xyz.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) pd->GetPoint(i, &cloud.xyz[3 * i]);
  for (int k = 0; k < pd->GetPointData()->GetNumberOfArrays(); ++k)
    if (auto* d = pd->GetPointData()->GetArray(k)) cloud.point_data.push_back(from_vtk(d));
  read_field_data(pd, cloud);
  if (vtkCellArray* lines = pd->GetLines(); lines && lines->GetNumberOfCells() > 0) {
    const vtkIdType first_line = pd->GetNumberOfVerts();
    auto it = vtk::TakeSmartPointer(lines->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
      vtkIdType np;
      const vtkIdType* ids;
      it->GetCurrentCell(np, ids);
      STRATA_CHECK(np == 2, IO, "{}: line cell with {} points (only 2-point lines are read)", path.string(),
                   np);
      out.lines.ends.push_back(ids[0]);
      out.lines.ends.push_back(ids[1]);
    }
    // Cell data of a PolyData is ordered verts, lines, polys, strips: take the line part.
    const auto m = static_cast<vtkIdType>(out.lines.size());
    for (int k = 0; k < pd->GetCellData()->GetNumberOfArrays(); ++k) {
      auto* d = pd->GetCellData()->GetArray(k);
      if (!d) continue;
      Array a = from_vtk(d);
      const auto c = static_cast<std::size_t>(a.components);
      a.values =
          std::vector<double>(a.values.begin() + first_line * c, a.values.begin() + (first_line + m) * c);
      out.lines.cell_data.push_back(std::move(a));
    }
  }
  return out;
}

namespace detail {
vtkSmartPointer<vtkUnstructuredGrid> mesh_grid(const MeshFrame& mesh) {
  auto ug = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  const auto n = static_cast<vtkIdType>(mesh.nodes());
  pts->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i) pts->SetPoint(i, &mesh.xyz[3 * static_cast<std::size_t>(i)]);
  ug->SetPoints(pts);
  // Cells as offsets + connectivity, with one VTK cell type per cell.
  const auto m = static_cast<vtkIdType>(mesh.cells());
  vtkNew<vtkIdTypeArray> offsets, conn;
  offsets->SetNumberOfValues(m + 1);
  conn->SetNumberOfValues(static_cast<vtkIdType>(mesh.connectivity.size()));
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(m);
  vtkIdType at = 0;
  for (vtkIdType c = 0; c < m; ++c) {
    offsets->SetValue(c, at);
    types->SetValue(c, static_cast<unsigned char>(mesh.cell_types[static_cast<std::size_t>(c)]));
    at += nodes_per_cell(mesh.cell_types[static_cast<std::size_t>(c)]);
  }
  offsets->SetValue(m, at);
  for (vtkIdType k = 0; k < at; ++k) conn->SetValue(k, mesh.connectivity[static_cast<std::size_t>(k)]);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);
  ug->SetCells(types, cells);
  return ug;
}
}  // namespace detail

void write_mesh(const std::filesystem::path& path, const MeshFrame& mesh) {
  validate(mesh);
  const vtkSmartPointer<vtkUnstructuredGrid> ug = detail::mesh_grid(mesh);
  for (const auto& a : mesh.point_data) ug->GetPointData()->AddArray(to_vtk(a));
  for (const auto& a : mesh.cell_data) ug->GetCellData()->AddArray(to_vtk(a));
  add_field_data(ug, mesh);
  write_xml<vtkXMLUnstructuredGridWriter>(path, ug);
}

MeshFrame read_vtu(const std::filesystem::path& path) {
  STRATA_CHECK(std::filesystem::exists(path), IO, "cannot read {}: no such file", path.string());
  vtkNew<vtkXMLUnstructuredGridReader> r;
  read_checked(r, path);
  vtkUnstructuredGrid* ug = r->GetOutput();
  MeshFrame out;
  const vtkIdType n = ug->GetNumberOfPoints();
  out.xyz.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) ug->GetPoint(i, &out.xyz[3 * static_cast<std::size_t>(i)]);
  for (vtkIdType c = 0; c < ug->GetNumberOfCells(); ++c) {
    const int t = ug->GetCellType(c);
    STRATA_CHECK(t == VTK_LINE || t == VTK_TRIANGLE || t == VTK_TETRA, IO,
                 "{}: cell {} has VTK type {} (only lines, triangles and tetrahedra are read)", path.string(),
                 c, t);
    vtkIdType np;
    const vtkIdType* ids;
    ug->GetCellPoints(c, np, ids);
    out.cell_types.push_back(static_cast<CellType>(t));
    out.connectivity.insert(out.connectivity.end(), ids, ids + np);
  }
  for (int k = 0; k < ug->GetPointData()->GetNumberOfArrays(); ++k)
    if (auto* d = ug->GetPointData()->GetArray(k)) out.point_data.push_back(from_vtk(d));
  for (int k = 0; k < ug->GetCellData()->GetNumberOfArrays(); ++k)
    if (auto* d = ug->GetCellData()->GetArray(k)) out.cell_data.push_back(from_vtk(d));
  read_field_data(ug, out);
  return out;
}

#else  // !STRATA_WITH_VTK

void write_particles(const std::filesystem::path&, const PointCloud&) {
  fail_missing_feature("STRATA_WITH_VTK", "VTK time series");
}
void write_lines(const std::filesystem::path&, const PointCloud&, const LineSet&) {
  fail_missing_feature("STRATA_WITH_VTK", "VTK time series");
}
VtpContents read_vtp(const std::filesystem::path&) {
  fail_missing_feature("STRATA_WITH_VTK", "VTK time series");
}
void write_mesh(const std::filesystem::path&, const MeshFrame&) {
  fail_missing_feature("STRATA_WITH_VTK", "VTK time series");
}
MeshFrame read_vtu(const std::filesystem::path&) {
  fail_missing_feature("STRATA_WITH_VTK", "VTK time series");
}

#endif

}  // namespace strata::io
