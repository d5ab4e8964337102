// Nanoseconds per query of surface_synthesis' three neighbourhood searches on the Fig. 7 finest
// level's table: a 64 x 64 exemplar (data/images/pebbles05.png reduced 4x by box averaging, or a
// smooth procedural image when the file is missing), neighbourhood {7x7, 2}: 48 current samples +
// 3 x 3 coarser samples, RGB = 171 values, 4096 rows. Queries are the same neighbourhoods read
// from another exemplar-sized view of the image (the 2x reduction's centre), so they resemble
// the vectors synthesis compares. Reports per method the build time, ns per query (median over
// --repeats; exhaustive both one query at a time and in one batch), bytes held, and for TSVQ the
// fraction of queries answered exactly and the mean distance relative to the exact one, for
// pruned the mean number of full distances per query. Runs on rank 0, one thread unless
// OMP_NUM_THREADS says otherwise (the batch uses the threads). --components sets the pruned
// search's m.
// Prints one JSON object.
// Sample run:
//   OMP_NUM_THREADS=1 build/release/bench/neighbourhood_search_bench --queries 4096 --repeats 3
#include "bench_timing.hpp"
#include "img/image_io.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"
#include "pipelines/surface_synthesis/pruned_search.hpp"
#include "pipelines/surface_synthesis/tsvq_tree.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

namespace {
using namespace texsim;
using namespace texsim::pipelines::surface_synthesis;

struct BenchSettings {
  std::string image = "data/images/pebbles05.png";
  int queries = 4096;
  int repeats = 3;
  SearchOptions options;
};

BenchSettings parse_arguments(int argc, char** argv) {
  BenchSettings s;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--image")
      s.image = argv[i + 1];
    else if (flag == "--queries")
      s.queries = std::stoi(argv[i + 1]);
    else if (flag == "--repeats")
      s.repeats = std::stoi(argv[i + 1]);
    else if (flag == "--components")
      s.options.pruned_components = std::stoi(argv[i + 1]);
    else
      throw std::runtime_error("unknown option " + flag);
  }
  return s;
}

/// The image reduced by `factor` (box average), then `size` x `size` pixels from (x0, y0), wrapped.
img::RgbImage reduced_view(const img::RgbImage& image, int factor, int x0, int y0, int size) {
  img::RgbImage out(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      img::Rgb sum{};
      for (int dy = 0; dy < factor; ++dy)
        for (int dx = 0; dx < factor; ++dx)
          sum += image.periodic((x0 + x) * factor + dx, (y0 + y) * factor + dy);
      sum *= 1.0f / static_cast<float>(factor * factor);
      out.at(x, y) = sum;
    }
  return out;
}

img::RgbImage procedural(int size) {
  img::RgbImage out(size * 4, size * 4);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double u = 2.0 * std::numbers::pi * x / out.width();
        const double v = 2.0 * std::numbers::pi * y / out.height();
        out.at(x, y)[c] =
            static_cast<float>(0.5 + 0.25 * std::sin(5.0 * u + c) * std::cos(7.0 * v) +
                               0.2 * std::sin(11.0 * u + 3.0 * v + c));
      }
  return out;
}

/// The 171-value neighbourhood of every pixel of `fine` (toroidal): 7 x 7 without the centre, then
/// 3 x 3 of `coarse` around (x / 2, y / 2), RGB.
std::vector<double> neighbourhoods(const img::RgbImage& fine, const img::RgbImage& coarse) {
  std::vector<double> out;
  for (int y = 0; y < fine.height(); ++y)
    for (int x = 0; x < fine.width(); ++x) {
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx)
          if (dx != 0 || dy != 0)
            for (int c = 0; c < 3; ++c)
              out.push_back(fine.periodic(x + dx, y + dy)[c]);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          for (int c = 0; c < 3; ++c)
            out.push_back(coarse.periodic(x / 2 + dx, y / 2 + dy)[c]);
    }
  return out;
}

double median_seconds(int repeats, const std::function<void()>& work) {
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    const double start = MPI_Wtime();
    work();
    times.push_back(MPI_Wtime() - start);
  }
  return bench::median(times);
}

} // namespace

int main(int argc, char** argv) {
  par::PetscSession session(argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0)
    return 0;
  const BenchSettings s = parse_arguments(argc, argv);
  const int size = 64;
  const bool real = std::filesystem::exists(s.image);
  const img::RgbImage source = real ? img::read_image(s.image) : procedural(size);
  const int factor = source.width() / size;
  const img::RgbImage exemplar = reduced_view(source, factor, 0, 0, size);
  const img::RgbImage exemplar_coarse = reduced_view(source, 2 * factor, 0, 0, size / 2);
  const std::vector<double> rows = neighbourhoods(exemplar, exemplar_coarse);
  NeighbourhoodTable table{171, std::vector<float>(rows.begin(), rows.end())};

  // Query views: the 2x reduction around the image's centre (other pixels, other scale).
  const int half = factor / 2 > 0 ? factor / 2 : 1;
  const img::RgbImage other = reduced_view(source, half, size / 2, size / 2, size);
  const img::RgbImage other_coarse = reduced_view(source, 2 * half, size / 4, size / 4, size / 2);
  const std::vector<double> view = neighbourhoods(other, other_coarse);
  std::vector<double> queries;
  for (int i = 0; i < s.queries; ++i) {
    const auto pixel = static_cast<std::size_t>((i * 2654435761u) % (size * size));
    queries.insert(queries.end(), view.begin() + pixel * 171, view.begin() + (pixel + 1) * 171);
  }
  const auto query = [&](int i) {
    return std::span<const double>(queries).subspan(static_cast<std::size_t>(i) * 171, 171);
  };
  const double per_query = 1e9 / s.queries;

  nlohmann::json result{{"benchmark", "neighbourhood_search"},
                        {"table", real ? s.image : "procedural"},
                        {"rows", table.rows()},
                        {"dimension", table.dimension},
                        {"queries", s.queries},
                        {"threads", omp_get_max_threads()}};

  std::vector<std::int64_t> exact(static_cast<std::size_t>(s.queries));
  std::unique_ptr<NeighbourhoodSearch> search;
  double build = median_seconds(
      1, [&] { search = make_neighbourhood_search(SearchMethod::exhaustive, table); });
  const double exhaustive_single = median_seconds(s.repeats, [&] {
    for (int i = 0; i < s.queries; ++i)
      exact[static_cast<std::size_t>(i)] = search->nearest(query(i));
  });
  const double exhaustive_batch =
      median_seconds(s.repeats, [&] { search->nearest_batch(queries, exact); });
  result["exhaustive"] = {{"build_s", build},
                          {"ns_per_query", exhaustive_single * per_query},
                          {"ns_per_query_batch", exhaustive_batch * per_query},
                          {"memory_bytes", search->memory_bytes()}};
  const auto& reference = *search;
  std::vector<double> exact_distance(exact.size());
  for (int i = 0; i < s.queries; ++i)
    exact_distance[static_cast<std::size_t>(i)] =
        reference.distance2(exact[static_cast<std::size_t>(i)], query(i));

  std::unique_ptr<NeighbourhoodSearch> tsvq;
  build = median_seconds(
      1, [&] { tsvq = make_neighbourhood_search(SearchMethod::tsvq, table, s.options); });
  std::vector<std::int64_t> found(exact.size());
  const double tsvq_time = median_seconds(s.repeats, [&] {
    for (int i = 0; i < s.queries; ++i)
      found[static_cast<std::size_t>(i)] = tsvq->nearest(query(i));
  });
  int same = 0;
  double ratio = 0.0;
  for (int i = 0; i < s.queries; ++i) {
    const auto k = static_cast<std::size_t>(i);
    same += found[k] == exact[k];
    const double approximate = reference.distance2(found[k], query(i));
    ratio += exact_distance[k] > 0.0 ? std::sqrt(approximate / exact_distance[k]) : 1.0;
  }
  result["tsvq"] = {{"build_s", build},
                    {"ns_per_query", tsvq_time * per_query},
                    {"memory_bytes", tsvq->memory_bytes()},
                    {"depth", dynamic_cast<const TsvqSearch&>(*tsvq).depth()},
                    {"exact_fraction", static_cast<double>(same) / s.queries},
                    {"mean_distance_ratio", ratio / s.queries}};

  std::unique_ptr<NeighbourhoodSearch> pruned;
  build = median_seconds(
      1, [&] { pruned = make_neighbourhood_search(SearchMethod::pruned, table, s.options); });
  const double pruned_time = median_seconds(s.repeats, [&] {
    for (int i = 0; i < s.queries; ++i)
      found[static_cast<std::size_t>(i)] = pruned->nearest(query(i));
  });
  std::int64_t checked = 0;
  const auto& bounds = dynamic_cast<const PrunedSearch&>(*pruned);
  for (int i = 0; i < s.queries; ++i)
    checked += static_cast<std::int64_t>(bounds.candidates(query(i)).size());
  result["pruned"] = {{"build_s", build},
                      {"ns_per_query", pruned_time * per_query},
                      {"memory_bytes", pruned->memory_bytes()},
                      {"components", bounds.components()},
                      {"exact", found == exact},
                      {"mean_full_distances", static_cast<double>(checked) / s.queries}};
  std::cout << result.dump(1) << std::endl;
  return 0;
}
