// Bezier meshes of NURBS checked with VTK itself: the test writes the .vtu and a CSV of cell-parametric
// points with fibrane's NURBS evaluation of the deformed geometry and of the fields there;
// tests/io/check_bezier_vtu.py reads the file with vtkXMLUnstructuredGridReader, evaluates the Bezier
// cells at those points and compares. Tolerance 1e-12 relative to the model size (positions) or the
// field's magnitude: both sides sum at most 25 rational Bernstein or NURBS terms of O(size) values, so
// the round-off is a few 1e-15; a cell with its points out of VTK's order or without its weights is
// off by 1e-3 or more.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "io/bezier_vtu.hpp"
#include "io/csv.hpp"
#include "io/scratch_dir.hpp"
#include "spline/shapes.hpp"

namespace fibrane::io {
namespace {

struct Sample {
  int cell;
  double r, s;
  Eigen::Vector3d x;
  std::vector<double> fields;  // the components of all fields, in the order of the fields
};

// Per-control-point displacement (smooth in the reference position) and a scalar "twist".
std::vector<VtuMesh::Field> control_fields(const std::vector<Eigen::Vector3d>& reference) {
  VtuMesh::Field displacement{"displacement", 3, {}}, twist{"twist", 1, {}};
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const Eigen::Vector3d& X = reference[i];
    displacement.values.insert(displacement.values.end(),
                               {0.3 * std::sin(2 * X.y()), 0.2 * std::cos(X.x()) * X.z(), 0.1 * X.x() * X.y()});
    twist.values.push_back(std::sin(0.7 * static_cast<double>(i)));
  }
  return {displacement, twist};
}

std::vector<Eigen::Vector3d> displaced(const std::vector<Eigen::Vector3d>& reference, const VtuMesh::Field& u) {
  std::vector<Eigen::Vector3d> current = reference;
  for (std::size_t i = 0; i < current.size(); ++i) current[i] += Eigen::Vector3d(&u.values[3 * i]);
  return current;
}

// sum_a R_a (current point, field values) over the control points `indices` with basis values `r`.
Sample nurbs_sample(int cell, double r, double s, const std::vector<int>& indices, const Eigen::RowVectorXd& basis,
                    const std::vector<Eigen::Vector3d>& current, const std::vector<VtuMesh::Field>& fields) {
  Sample out{cell, r, s, Eigen::Vector3d::Zero(), {}};
  for (std::size_t a = 0; a < indices.size(); ++a) out.x += basis[a] * current[indices[a]];
  for (const auto& f : fields)
    for (int c = 0; c < f.components; ++c) {
      double value = 0.0;
      for (std::size_t a = 0; a < indices.size(); ++a) value += basis[a] * f.values[indices[a] * f.components + c];
      out.fields.push_back(value);
    }
  return out;
}

// Cell-parametric points: the corners, the edge midpoints and random interior points.
std::vector<std::pair<double, double>> parametric_points(std::mt19937& rng, bool curve) {
  std::vector<std::pair<double, double>> points{{0, 0}, {1, 0}, {0.5, 0}};
  if (!curve) points.insert(points.end(), {{1, 1}, {0, 1}, {1, 0.5}, {0.5, 1}, {0, 0.5}});
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 6; ++k) points.emplace_back(unit(rng), curve ? 0.0 : unit(rng));
  return points;
}

void write_samples(const std::string& path, const std::vector<VtuMesh::Field>& fields, const std::vector<Sample>& samples) {
  std::string text = "cell,r,s,x,y,z";
  for (const auto& f : fields)
    for (int c = 0; c < f.components; ++c) text.append(",").append(f.name).append(":").append(std::to_string(c));
  text += "\n";
  for (const auto& sample : samples) {
    text += std::to_string(sample.cell);
    for (const double v : {sample.r, sample.s, sample.x.x(), sample.x.y(), sample.x.z()}) text.append(",").append(format_double(v));
    for (const double v : sample.fields) text.append(",").append(format_double(v));
    text += "\n";
  }
  testing::write_text(path, text);
}

// Writes mesh and samples, runs the checker and returns its exit code; the checker's report goes to
// the test log.
int check_with_vtk(const testing::ScratchDir& dir, const VtuMesh& mesh, const std::vector<VtuMesh::Field>& fields,
                   const std::vector<Sample>& samples, VtuEncoding encoding) {
  write_vtu(dir.file("mesh.vtu"), mesh, encoding);
  write_samples(dir.file("points.csv"), fields, samples);
  const std::string command = "/usr/bin/python3 " FIBRANE_SOURCE_DIR "/tests/io/check_bezier_vtu.py " +
                              dir.file("mesh.vtu") + " " + dir.file("points.csv") + " 1e-12";
  return std::system(command.c_str());
}

// A sphere patch (rational in both directions) elevated to degrees 3 x 4, refined, with a C0 knot.
spline::NurbsSurface sphere_patch() {
  spline::NurbsSurface sphere = spline::make_sphere_patch(2.0, 0.3, 2.2, -0.7, 1.1);
  sphere.refine(0, 3, 1, 3);
  sphere.refine(1, 4, 2, 2);
  sphere.insert_knot(0, 0.55, 3);
  return sphere;
}

class BezierVtu : public ::testing::TestWithParam<VtuEncoding> {};

TEST_P(BezierVtu, VtkEvaluatesTheDeformedSpherePatchExactly) {
  if (!testing::python_has("vtk")) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk";
  const spline::NurbsSurface sphere = sphere_patch();
  const auto fields = control_fields(sphere.control_points());
  const auto current = displaced(sphere.control_points(), fields[0]);
  const VtuMesh mesh = bezier_surface_vtu(sphere, current, fields);
  const auto elements = sphere.elements();
  ASSERT_EQ(mesh.types.size(), elements.size());
  EXPECT_EQ(mesh.points.size(), (3u * sphere.knots(0).num_elements() + 1) * (4u * sphere.knots(1).num_elements() + 1));

  std::mt19937 rng(1);
  std::vector<Sample> samples;
  for (std::size_t c = 0; c < elements.size(); ++c) {
    const auto& el = elements[c];
    for (const auto& [r, s] : parametric_points(rng, false)) {
      const auto basis = sphere.basis_in(el.span_u, el.span_v, el.u0 + r * (el.u1 - el.u0), el.v0 + s * (el.v1 - el.v0));
      samples.push_back(nurbs_sample(static_cast<int>(c), r, s, basis.indices, basis.R.row(0), current, fields));
    }
  }
  testing::ScratchDir dir;
  EXPECT_EQ(check_with_vtk(dir, mesh, fields, samples, GetParam()), 0);
}

TEST_P(BezierVtu, VtkEvaluatesTheDeformedArcExactly) {
  if (!testing::python_has("vtk")) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk";
  spline::NurbsCurve arc = spline::make_arc({0.5, 0, -1}, {1, 0, 0}, {0, 0.6, 0.8}, 1.5, 0.0, 4.0);
  arc.refine(4, 2, 5);
  const auto fields = control_fields(arc.control_points());
  const auto current = displaced(arc.control_points(), fields[0]);
  const VtuMesh mesh = bezier_curve_vtu(arc, current, fields);
  const auto spans = arc.knots().element_spans();
  ASSERT_EQ(mesh.types.size(), spans.size());
  EXPECT_EQ(mesh.points.size(), 4 * spans.size() + 1);

  std::mt19937 rng(2);
  std::vector<Sample> samples;
  for (std::size_t c = 0; c < spans.size(); ++c) {
    const double u0 = arc.knots().knots()[spans[c]], u1 = arc.knots().knots()[spans[c] + 1];
    for (const auto& [r, s] : parametric_points(rng, true)) {
      const auto basis = arc.basis(u0 + r * (u1 - u0), 0);
      std::vector<int> indices(basis.R.cols());
      for (int a = 0; a < basis.R.cols(); ++a) indices[a] = basis.first + a;
      samples.push_back(nurbs_sample(static_cast<int>(c), r, s, indices, basis.R.row(0), current, fields));
    }
  }
  testing::ScratchDir dir;
  EXPECT_EQ(check_with_vtk(dir, mesh, fields, samples, GetParam()), 0);
}

INSTANTIATE_TEST_SUITE_P(Encodings, BezierVtu, ::testing::Values(VtuEncoding::compressed, VtuEncoding::ascii),
                         [](const auto& info) {
                           return std::string(info.param == VtuEncoding::compressed ? "compressed" : "ascii");
                         });

TEST(BezierVtu, WrongSizesAndReservedNamesAreRejected) {
  const spline::NurbsSurface sphere = sphere_patch();
  auto current = sphere.control_points();
  auto fields = control_fields(current);
  EXPECT_NO_THROW(bezier_surface_vtu(sphere, current, fields));
  fields[1].values.pop_back();
  EXPECT_THROW(bezier_surface_vtu(sphere, current, fields), std::invalid_argument);
  EXPECT_THROW(bezier_surface_vtu(sphere, current, {{vtk_bezier::weights, 1, std::vector<double>(current.size())}}),
               std::invalid_argument);
  current.pop_back();
  EXPECT_THROW(bezier_surface_vtu(sphere, current), std::invalid_argument);
}

TEST(BezierVtu, CompressedAndAsciiSizes) {
  const spline::NurbsSurface sphere = sphere_patch();
  const auto fields = control_fields(sphere.control_points());
  const VtuMesh mesh = bezier_surface_vtu(sphere, displaced(sphere.control_points(), fields[0]), fields);
  const std::size_t compressed = vtu_document(mesh, VtuEncoding::compressed).size();
  const std::size_t ascii = vtu_document(mesh, VtuEncoding::ascii).size();
  RecordProperty("bytes_compressed", std::to_string(compressed));
  RecordProperty("bytes_ascii", std::to_string(ascii));
  EXPECT_LT(compressed, ascii);
}

}  // namespace
}  // namespace fibrane::io
