#include "pipelines/fem_rd/loop_assembler.hpp"

#include "core/error.hpp"
#include "geom/loop_box_spline.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace texsim::pipelines::fem_rd {
namespace {

/// Points (s, t) and weights of a quadrature rule on the parameter triangle (weights sum to 1/2).
struct TriangleRule {
  std::vector<std::array<double, 2>> points;
  std::vector<double> weights;
};

/// The collapsed (Duffy) product of 4-point Gauss-Legendre rules: exact for polynomials of
/// degree 7 in s, t.
TriangleRule collapsed_gauss_rule() {
  const double inner = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
  const double outer = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
  const double inner_weight = (18.0 + std::sqrt(30.0)) / 36.0;
  const double outer_weight = (18.0 - std::sqrt(30.0)) / 36.0;
  // Nodes and weights on [0, 1].
  const std::array<double, 4> x{(1 - outer) / 2, (1 - inner) / 2, (1 + inner) / 2, (1 + outer) / 2};
  const std::array<double, 4> w{outer_weight / 2, inner_weight / 2, inner_weight / 2,
                                outer_weight / 2};
  TriangleRule rule;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      rule.points.push_back({x[i], x[j] * (1 - x[i])});
      rule.weights.push_back(w[i] * w[j] * (1 - x[i]));
    }
  return rule;
}

/// The rule on each of the n^2 sub-triangles of the parameter triangle cut n times per side.
TriangleRule subdivided_rule(const TriangleRule& rule, int n) {
  TriangleRule result;
  const auto add = [&](std::array<double, 2> p0, std::array<double, 2> p1,
                       std::array<double, 2> p2) {
    for (std::size_t q = 0; q < rule.points.size(); ++q) {
      const auto [s, t] = rule.points[q];
      result.points.push_back({(p0[0] + s * (p1[0] - p0[0]) + t * (p2[0] - p0[0])) / n,
                               (p0[1] + s * (p1[1] - p0[1]) + t * (p2[1] - p0[1])) / n});
      result.weights.push_back(rule.weights[q] / double(n * n));
    }
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const double a = i, b = j;
      add({a, b}, {a + 1, b}, {a, b + 1});
      if (i + j + 1 < n)
        add({a + 1, b}, {a + 1, b + 1}, {a, b + 1});
    }
  return result;
}

/// Sub-triangles per side of an irregular triangle's quadrature: one subdivision, 64 points. On
/// the sphere test 1, 2 and 4 give the same errors to 3e-5 relative; 2 leaves room for the
/// rougher functions around high or low valences.
constexpr int kIrregularSplit = 2;

} // namespace

LoopAssembler::Table
LoopAssembler::irregular_table(const geom::LoopPatchBasis& basis, std::int32_t t,
                               const std::vector<std::array<double, 2>>& points,
                               const std::vector<double>& weights) {
  Table table;
  const auto count = Eigen::Index(points.size());
  const auto functions = Eigen::Index(basis.controls(t).size());
  table.weight = weights;
  table.value.resize(count, functions);
  table.d_s.resize(count, functions);
  table.d_t.resize(count, functions);
  geom::PatchBasisValues values;
  for (Eigen::Index q = 0; q < count; ++q) {
    const auto [s, u] = points[std::size_t(q)];
    basis.evaluate(t, s, u, values);
    for (Eigen::Index k = 0; k < functions; ++k) {
      table.value(q, k) = values.value[std::size_t(k)];
      table.d_s(q, k) = values.d_s[std::size_t(k)];
      table.d_t(q, k) = values.d_t[std::size_t(k)];
    }
  }
  return table;
}

namespace {

ElementAssembly element_assembly(const geom::DistributedMesh& mesh,
                                 const std::vector<std::int64_t>& offsets,
                                 const std::vector<std::int32_t>& controls) {
  std::vector<std::int32_t> functions;
  functions.reserve(controls.size());
  for (const std::int32_t local : controls)
    functions.push_back(mesh.global_index(local));
  return {mesh.owned_begin(), mesh.owned_end(), offsets, functions};
}

} // namespace

LoopAssembler::ElementList LoopAssembler::list_elements(const geom::DistributedMesh& mesh) {
  const geom::LoopPatchBasis basis(mesh.mesh(), mesh.topology(), mesh.creases());
  ElementList list;
  const auto& triangles = mesh.mesh().triangles;
  for (std::int32_t t = 0; t < mesh.mesh().num_triangles(); ++t) {
    const auto& tri = triangles[std::size_t(t)];
    if (tri[0] >= mesh.local_count() && tri[1] >= mesh.local_count() &&
        tri[2] >= mesh.local_count())
      continue; // no corner within one ring of an owned vertex
    // The mesh section splits non-manifold vertices, and the halo holds the stars of these
    // triangles' corners: every corner has one fan, closed or ending on the boundary.
    TEXSIM_VERIFY(basis.evaluable(t), "Loop basis: triangle " << t
                                                              << " has a corner of several fans "
                                                                 "or outside this rank's halo");
    const auto controls = basis.controls(t);
    list.triangles.push_back(t);
    list.controls.insert(list.controls.end(), controls.begin(), controls.end());
    list.offsets.push_back(std::int64_t(list.controls.size()));
  }
  return list;
}

LoopAssembler::LoopAssembler(const geom::DistributedMesh& mesh)
    : LoopAssembler(mesh, list_elements(mesh)) {}

LoopAssembler::LoopAssembler(const geom::DistributedMesh& mesh, ElementList list)
    : FemAssembler(element_assembly(mesh, list.offsets, list.controls)), mesh_(mesh),
      controls_(std::move(list.controls)) {
  const TriangleRule regular_rule = collapsed_gauss_rule();
  const TriangleRule irregular_rule = subdivided_rule(regular_rule, kIrregularSplit);
  Table regular;
  const auto regular_points = Eigen::Index(regular_rule.points.size());
  TEXSIM_VERIFY(regular_points == kRegularPoints, "Loop basis: " << regular_points << " points");
  regular.weight = regular_rule.weights;
  regular.value.resize(regular_points, 12);
  regular.d_s.resize(regular_points, 12);
  regular.d_t.resize(regular_points, 12);
  for (Eigen::Index q = 0; q < regular_points; ++q) {
    const auto [s, t] = regular_rule.points[std::size_t(q)];
    const auto basis = geom::regular_patch_basis(s, t);
    for (Eigen::Index k = 0; k < 12; ++k) {
      regular.value(q, k) = basis.value[std::size_t(k)];
      regular.d_s(q, k) = basis.d_s[std::size_t(k)];
      regular.d_t(q, k) = basis.d_t[std::size_t(k)];
    }
  }
  tables_.push_back(std::move(regular));

  const geom::LoopPatchBasis basis(mesh.mesh(), mesh.topology(), mesh.creases());
  std::map<std::vector<std::int32_t>, std::size_t> table_of_structure;
  std::size_t points = 0;
  for (std::size_t e = 0; e < list.triangles.size(); ++e) {
    const std::int32_t t = list.triangles[e];
    Element element;
    element.triangle = t;
    element.first_control = std::size_t(list.offsets[e]);
    element.first_point = points;
    if (!basis.is_regular(t)) {
      // One table per class of equal structure, as the paper computes its irregular patches.
      const auto [known, inserted] = table_of_structure.emplace(basis.structure(t), tables_.size());
      element.table = known->second;
      if (inserted)
        tables_.push_back(irregular_table(basis, t, irregular_rule.points, irregular_rule.weights));
    }
    points += tables_[element.table].weight.size();
    elements_.push_back(element);
  }
  measure_.resize(points);
  dual_s_.resize(points);
  dual_t_.resize(points);
  update_geometry();
}

std::size_t LoopAssembler::irregular_count() const {
  return std::size_t(std::count_if(elements_.begin(), elements_.end(),
                                   [](const Element& e) { return e.table != 0; }));
}

std::string LoopAssembler::description() const {
  return "Loop C1 box splines, " + std::to_string(elements_.size()) + " elements (" +
         std::to_string(irregular_count()) + " irregular in " +
         std::to_string(irregular_class_count()) + " classes of equal structure, " +
         std::to_string(measure_.size()) + " quadrature points)";
}

void LoopAssembler::update_geometry() {
  const auto& positions = mesh_.mesh().positions;
  const auto count = std::int64_t(elements_.size());
  std::int64_t degenerate = count;
#pragma omp parallel for schedule(static) reduction(min : degenerate)
  for (std::int64_t e = 0; e < count; ++e) {
    const Element& element = elements_[std::size_t(e)];
    const Table& table = tables_[element.table];
    for (Eigen::Index q = 0; q < table.value.rows(); ++q) {
      Eigen::Vector3d x_s = Eigen::Vector3d::Zero(), x_t = Eigen::Vector3d::Zero();
      for (Eigen::Index k = 0; k < table.value.cols(); ++k) {
        const auto& x = positions[std::size_t(controls_[element.first_control + std::size_t(k)])];
        x_s += table.d_s(q, k) * x;
        x_t += table.d_t(q, k) * x;
      }
      const double e_ss = x_s.dot(x_s), e_st = x_s.dot(x_t), e_tt = x_t.dot(x_t);
      const double det = e_ss * e_tt - e_st * e_st;
      const std::size_t point = element.first_point + std::size_t(q);
      if (!(det > 0)) {
        degenerate = std::min(degenerate, e);
        continue;
      }
      measure_[point] = table.weight[std::size_t(q)] * std::sqrt(det);
      dual_s_[point] = (e_tt * x_s - e_st * x_t) / det;
      dual_t_[point] = (e_ss * x_t - e_st * x_s) / det;
    }
  }
  TEXSIM_VERIFY(degenerate == count, "Loop basis: the limit surface is degenerate on triangle "
                                         << elements_[std::size_t(degenerate)].triangle);
}

std::vector<double> LoopAssembler::mass_values(std::span<const double> weight, bool lumped) const {
  // Every entry is written below: no zero fill (this runs every step).
  const std::unique_ptr<double[]> entries(new double[std::size_t(assembly_.entry_count())]);
  const auto count = std::int64_t(elements_.size());
  // Regular elements (nearly all) in fixed-size matrices, as sums over the points of the shared
  // products phi_i phi_j (i <= j): this runs every step.
  using RegularValues = Eigen::Matrix<double, kRegularPoints, 12>;
  const RegularValues regular = tables_.front().value;
  Eigen::Matrix<double, 78, kRegularPoints> products;
  for (int i = 0, pair = 0; i < 12; ++i)
    for (int j = i; j < 12; ++j, ++pair)
      products.row(pair) = regular.col(i).cwiseProduct(regular.col(j)).transpose();
#pragma omp parallel for schedule(static)
  for (std::int64_t e = 0; e < count; ++e) {
    const Element& element = elements_[std::size_t(e)];
    const Table& table = tables_[element.table];
    const Eigen::Index functions = table.value.cols();
    const auto control_weight = [&](Eigen::Index k) {
      return weight[std::size_t(controls_[element.first_control + std::size_t(k)])];
    };
    const auto store = [&](const auto& block) {
      double* out = entries.get() + assembly_.entry_offset(std::size_t(e));
      for (Eigen::Index i = 0; i < functions; ++i)
        for (Eigen::Index j = 0; j < functions; ++j) // lumped: the row sum int w phi_i
          out[i * functions + j] = lumped ? (i == j ? block.row(i).sum() : 0.0) : block(i, j);
    };
    if (element.table == 0) {
      Eigen::Matrix<double, kRegularPoints, 1> w =
          Eigen::Map<const Eigen::Matrix<double, kRegularPoints, 1>>(measure_.data() +
                                                                     element.first_point);
      if (!weight.empty()) {
        Eigen::Matrix<double, 12, 1> at_controls;
        for (Eigen::Index k = 0; k < 12; ++k)
          at_controls[k] = control_weight(k);
        w = w.cwiseProduct(regular * at_controls);
      }
      const Eigen::Matrix<double, 78, 1> sums = products * w;
      Eigen::Matrix<double, 12, 12> block;
      for (int i = 0, pair = 0; i < 12; ++i)
        for (int j = i; j < 12; ++j, ++pair)
          block(i, j) = block(j, i) = sums[pair];
      store(block);
      continue;
    }
    Eigen::VectorXd w(table.value.rows());
    for (Eigen::Index q = 0; q < w.size(); ++q) {
      double coefficient = 1.0;
      if (!weight.empty()) {
        coefficient = 0.0;
        for (Eigen::Index k = 0; k < functions; ++k)
          coefficient += table.value(q, k) * control_weight(k);
      }
      w[q] = measure_[element.first_point + std::size_t(q)] * coefficient;
    }
    const Eigen::MatrixXd block = table.value.transpose() * w.asDiagonal() * table.value;
    store(block);
  }
  return assembly_.sum_entries({entries.get(), std::size_t(assembly_.entry_count())});
}

std::vector<double> LoopAssembler::stiffness_values(std::span<const double> tensors) const {
  const std::unique_ptr<double[]> entries(new double[std::size_t(assembly_.entry_count())]);
  const auto count = std::int64_t(elements_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t e = 0; e < count; ++e) {
    const Element& element = elements_[std::size_t(e)];
    const Table& table = tables_[element.table];
    const Eigen::Index functions = table.value.cols();
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(functions, functions);
    Eigen::MatrixXd gradient(functions, 3);
    for (Eigen::Index q = 0; q < table.value.rows(); ++q) {
      const std::size_t point = element.first_point + std::size_t(q);
      for (Eigen::Index k = 0; k < functions; ++k)
        gradient.row(k) =
            (table.d_s(q, k) * dual_s_[point] + table.d_t(q, k) * dual_t_[point]).transpose();
      Eigen::Matrix3d tensor = Eigen::Matrix3d::Identity();
      if (!tensors.empty()) {
        tensor.setZero();
        for (Eigen::Index k = 0; k < functions; ++k)
          tensor += table.value(q, k) *
                    Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
                        tensors.data() +
                        9 * std::size_t(controls_[element.first_control + std::size_t(k)]));
      }
      block += measure_[point] * gradient * tensor * gradient.transpose();
    }
    double* out = entries.get() + assembly_.entry_offset(std::size_t(e));
    for (Eigen::Index i = 0; i < functions; ++i)
      for (Eigen::Index j = 0; j < functions; ++j)
        out[i * functions + j] = block(i, j);
  }
  return assembly_.sum_entries({entries.get(), std::size_t(assembly_.entry_count())});
}

} // namespace texsim::pipelines::fem_rd
