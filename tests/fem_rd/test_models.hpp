#pragma once
// Reaction models defined by the tests themselves, so the solver is checked against known
// solutions independently of the built-in models.
#include "core/rng.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_validation.hpp"
#include "rd/reaction_model.hpp"

#include <functional>

namespace texsim::pipelines::fem_rd::test {

/// A noisy level-3 icosphere of radius 5 without its cap above z = 3: an open surface, its
/// boundary loop's vertices on 2 to 4 triangles, its vertices of valence 5 and 6 inside.
inline geom::TriangleMesh sphere_without_its_cap() {
  geom::TriangleMesh mesh = geom::noisy(geom::icosphere(3, 5.0), 0.05, 9);
  std::erase_if(mesh.triangles, [&](const auto& tri) {
    return mesh.positions[tri[0]].z() + mesh.positions[tri[1]].z() + mesh.positions[tri[2]].z() >
           9.0;
  });
  geom::MeshRepairOptions options;
  options.split_non_manifold = true;
  geom::repair(mesh, options, "sphere without its cap");
  return mesh;
}

/// du/dt = Laplace u (C2 = C3 = 0), from u0(x, y, z).
class HeatModel : public rd::ReactionModel {
public:
  explicit HeatModel(std::function<double(double, double, double)> initial)
      : initial_(std::move(initial)) {}
  std::vector<std::string> species() const override { return {"u"}; }
  std::vector<std::vector<double>> initial_state(const rd::VertexData& vertices) const override {
    std::vector<double> u(vertices.size());
    for (std::size_t v = 0; v < u.size(); ++v)
      u[v] = initial_(vertices.xyz[3 * v], vertices.xyz[3 * v + 1], vertices.xyz[3 * v + 2]);
    return {u};
  }
  void coefficients(double, const std::vector<std::span<const double>>& state,
                    const rd::VertexData&,
                    std::vector<rd::SpeciesCoefficients>& out) const override {
    out.resize(1);
    out[0].diffusion = 1.0;
    out[0].linear.assign(state[0].size(), 0.0);
    out[0].source.assign(state[0].size(), 0.0);
  }

private:
  std::function<double(double, double, double)> initial_;
};

/// Fisher-KPP, du/dt = D Laplace u + u (1 - u), split as C2 = 1 - u^n, C3 = 0, from random
/// initial values keyed by vertex id: nonlinear, and its result depends on every vertex.
class FisherModel : public rd::ReactionModel {
public:
  std::vector<std::string> species() const override { return {"u"}; }
  std::vector<std::vector<double>> initial_state(const rd::VertexData& vertices) const override {
    const CounterRng rng(11, 5);
    std::vector<double> u(vertices.size());
    for (std::size_t v = 0; v < u.size(); ++v)
      u[v] = rng.uniform(std::uint64_t(vertices.ids[v]), 0);
    return {u};
  }
  void coefficients(double, const std::vector<std::span<const double>>& state,
                    const rd::VertexData&,
                    std::vector<rd::SpeciesCoefficients>& out) const override {
    out.resize(1);
    out[0].diffusion = 0.01;
    out[0].linear.resize(state[0].size());
    out[0].source.assign(state[0].size(), 0.0);
    for (std::size_t v = 0; v < state[0].size(); ++v)
      out[0].linear[v] = 1.0 - state[0][v];
  }
};

} // namespace texsim::pipelines::fem_rd::test
