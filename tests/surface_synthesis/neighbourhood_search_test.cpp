#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "pipelines/surface_synthesis/pruned_search.hpp"
#include "pipelines/surface_synthesis/tsvq_tree.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// The definition, one row at a time: sum over c of (double(v_c) - q_c)^2, argmin, ties to the
/// lower row.
std::int64_t brute_force(const NeighbourhoodTable& table, std::span<const double> query) {
  std::int64_t best = -1;
  double best_distance = 0.0;
  for (std::int64_t r = 0; r < table.rows(); ++r) {
    double sum = 0.0;
    for (int c = 0; c < table.dimension; ++c) {
      const double diff = static_cast<double>(table.values[r * table.dimension + c]) - query[c];
      sum += diff * diff;
    }
    if (best < 0 || sum < best_distance) {
      best = r;
      best_distance = sum;
    }
  }
  return best;
}

NeighbourhoodTable random_table(std::int64_t rows, int dimension, std::uint64_t seed) {
  NeighbourhoodTable table{dimension, {}};
  const CounterRng rng(seed, 0);
  for (std::int64_t i = 0; i < rows * dimension; ++i)
    table.values.push_back(static_cast<float>(rng.uniform(static_cast<std::uint64_t>(i), 0)));
  return table;
}

/// A table whose rows are repeated: row r + rows / 2 copies row r for even r.
NeighbourhoodTable table_with_duplicates(std::int64_t rows, int dimension, std::uint64_t seed) {
  NeighbourhoodTable table = random_table(rows, dimension, seed);
  for (std::int64_t r = 0; r < rows / 2; r += 2)
    std::copy_n(table.values.begin() + r * dimension, dimension,
                table.values.begin() + (r + rows / 2) * dimension);
  return table;
}

/// A smooth procedural RGB image, quantised to 8 bits (many equal and nearly equal
/// neighbourhoods, as in a real exemplar).
std::vector<float> smooth_image(int size, double phase) {
  std::vector<float> rgb(static_cast<std::size_t>(size) * size * 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) {
        const double u = 2.0 * std::numbers::pi * x / size, v = 2.0 * std::numbers::pi * y / size;
        const double value = 0.5 + 0.25 * std::sin(u + c + phase) * std::cos(2.0 * v - phase) +
                             0.2 * std::sin(3.0 * u + v + 0.5 * c);
        rgb[(static_cast<std::size_t>(y) * size + x) * 3 + c] =
            static_cast<float>(std::round(value * 255.0) / 255.0);
      }
  return rgb;
}

/// Wei-Levoy-like neighbourhood vectors of every pixel (toroidal): the 7 x 7 square without its
/// centre and a 3 x 3 coarser part read at twice the spacing, (48 + 9) x 3 = 171 values.
std::vector<double> neighbourhoods(const std::vector<float>& rgb, int size) {
  std::vector<double> out;
  const auto at = [&](int x, int y, int c) {
    x = ((x % size) + size) % size;
    y = ((y % size) + size) % size;
    return static_cast<double>(rgb[(static_cast<std::size_t>(y) * size + x) * 3 + c]);
  };
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx)
          if (dx != 0 || dy != 0)
            for (int c = 0; c < 3; ++c)
              out.push_back(at(x + dx, y + dy, c));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          for (int c = 0; c < 3; ++c)
            out.push_back(at(x + 2 * dx, y + 2 * dy, c));
    }
  return out;
}

NeighbourhoodTable image_table(int size) {
  const std::vector<double> vectors = neighbourhoods(smooth_image(size, 0.0), size);
  return {171, std::vector<float>(vectors.begin(), vectors.end())};
}

/// Queries: neighbourhoods of a phase-shifted image plus small noise, and exact rows of `table`.
std::vector<double> image_queries(const NeighbourhoodTable& table, int size, int count) {
  const std::vector<double> shifted = neighbourhoods(smooth_image(size, 0.7), size);
  const CounterRng rng(7, 1);
  std::vector<double> queries;
  for (int i = 0; i < count; ++i) {
    const auto pixel = static_cast<std::size_t>((i * 37) % (size * size));
    for (int c = 0; c < 171; ++c) {
      const auto index = static_cast<std::uint64_t>(i) * 171 + c;
      if (i % 4 == 3) // a row of the table itself: distance 0
        queries.push_back(table.values[pixel * 171 + c]);
      else
        queries.push_back(shifted[pixel * 171 + c] + 0.01 * rng.normal(index, 0));
    }
  }
  return queries;
}

std::vector<double> random_queries(int count, int dimension, std::uint64_t seed) {
  const CounterRng rng(seed, 2);
  std::vector<double> queries;
  for (int i = 0; i < count * dimension; ++i)
    queries.push_back(rng.uniform(-0.1, 1.1, static_cast<std::uint64_t>(i), 0));
  return queries;
}

std::span<const double> query_at(const std::vector<double>& queries, int dimension, int i) {
  return std::span(queries).subspan(static_cast<std::size_t>(i) * dimension,
                                    static_cast<std::size_t>(dimension));
}

TEST(ExhaustiveSearch, EqualsBruteForceOnRandomTables) {
  for (const int dimension : {1, 3, 17, 171}) {
    const NeighbourhoodTable table = table_with_duplicates(1000, dimension, 11 + dimension);
    const auto search = make_neighbourhood_search(SearchMethod::exhaustive, table);
    const int count = 300;
    std::vector<double> queries = random_queries(count, dimension, dimension);
    // Every fifth query is a duplicated row itself: distance 0 to two rows, the lower one wins.
    for (int i = 0; i < count; i += 5)
      for (int c = 0; c < dimension; ++c)
        queries[static_cast<std::size_t>(i) * dimension + c] =
            table.values[static_cast<std::size_t>(500 + 2 * (i % 50)) * dimension + c];
    std::vector<std::int64_t> batch(count);
    search->nearest_batch(queries, batch);
    for (int i = 0; i < count; ++i) {
      const auto query = query_at(queries, dimension, i);
      const std::int64_t expected = brute_force(table, query);
      ASSERT_EQ(search->nearest(query), expected) << "dimension " << dimension << " query " << i;
      ASSERT_EQ(batch[i], expected) << "dimension " << dimension << " query " << i;
      if (i % 5 == 0) {
        ASSERT_LT(expected, 500);
      }
    }
  }
}

TEST(ExhaustiveSearch, EquidistantQueriesGoToTheLowerRow) {
  // Rows on a 1/64 grid: the midpoint of two rows is exact, so both distances are equal sums of
  // the same squares.
  const int dimension = 20;
  NeighbourhoodTable table = random_table(200, dimension, 3);
  for (float& v : table.values)
    v = std::round(v * 64.0f) / 64.0f;
  const auto search = make_neighbourhood_search(SearchMethod::exhaustive, table);
  const auto pruned = make_neighbourhood_search(SearchMethod::pruned, table);
  for (int i = 0; i < 100; ++i) {
    const int a = (i * 7) % 200, b = (i * 13 + 5) % 200;
    if (a == b)
      continue;
    std::vector<double> query(dimension);
    for (int c = 0; c < dimension; ++c)
      query[c] = 0.5 * (static_cast<double>(table.values[a * dimension + c]) +
                        table.values[b * dimension + c]);
    ASSERT_EQ(search->distance2(a, query), search->distance2(b, query));
    const std::int64_t expected = brute_force(table, query);
    EXPECT_EQ(search->nearest(query), expected);
    EXPECT_EQ(pruned->nearest(query), expected);
    if (search->distance2(expected, query) == search->distance2(a, query)) {
      EXPECT_EQ(expected, std::min(a, b)) << "the tie between rows " << a << " and " << b;
    }
  }
}

TEST(ExhaustiveSearch, ExactWhereFloatRoundingOfTheQueryDecides) {
  // Rows one float ulp apart and queries between them: float(query) often lands on a row, so only
  // the scan's allowance for the query's rounding keeps the double argmin among the rows it
  // re-checks.
  for (const int dimension : {1, 3}) {
    NeighbourhoodTable table{dimension, {}};
    const int rows = 64;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < dimension; ++c) {
        float v = 1.0f + 0.25f * c;
        for (int k = 0; k < (r * 37) % rows; ++k) // rows in shuffled order
          v = std::nextafter(v, 2.0f);
        table.values.push_back(v);
      }
    const auto search = make_neighbourhood_search(SearchMethod::exhaustive, table);
    const auto pruned = make_neighbourhood_search(SearchMethod::pruned, table);
    const CounterRng rng(61, 4);
    const double ulp = std::ldexp(1.0, -23);
    for (int i = 0; i < 2000; ++i) {
      std::vector<double> query(dimension);
      for (int c = 0; c < dimension; ++c)
        query[c] = 1.0 + 0.25 * c + rng.uniform(-1.0, rows, static_cast<std::uint64_t>(i), c) * ulp;
      const std::int64_t expected = brute_force(table, query);
      ASSERT_EQ(search->nearest(query), expected) << "dimension " << dimension << " query " << i;
      ASSERT_EQ(pruned->nearest(query), expected) << "dimension " << dimension << " query " << i;
    }
  }
}

TEST(ExhaustiveSearch, BatchAnswersDoNotDependOnThreads) {
  const NeighbourhoodTable table = image_table(32);
  const auto search = make_neighbourhood_search(SearchMethod::exhaustive, table);
  const std::vector<double> queries = image_queries(table, 32, 301);
  std::vector<std::int64_t> one(301), two(301);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  search->nearest_batch(queries, one);
  omp_set_num_threads(2);
  search->nearest_batch(queries, two);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
  for (int i = 0; i < 301; i += 7)
    EXPECT_EQ(one[i], brute_force(table, query_at(queries, 171, i)));
}

TEST(ExhaustiveSearch, DistanceIsTheDefinition) {
  const NeighbourhoodTable table = random_table(50, 9, 4);
  const auto search = make_neighbourhood_search(SearchMethod::exhaustive, table);
  const std::vector<double> query = random_queries(1, 9, 5);
  for (std::int64_t r = 0; r < 50; ++r) {
    double sum = 0.0;
    for (int c = 0; c < 9; ++c) {
      const double diff = static_cast<double>(table.values[r * 9 + c]) - query[c];
      sum += diff * diff;
    }
    EXPECT_EQ(search->distance2(r, query), sum);
  }
}

TEST(ExhaustiveSearch, RefusesBadInput) {
  EXPECT_THROW(make_neighbourhood_search(SearchMethod::exhaustive, {3, {1.0f, 2.0f}}), Error);
  EXPECT_THROW(make_neighbourhood_search(SearchMethod::exhaustive, {2, {1.0f, NAN}}), Error);
  const auto search = make_neighbourhood_search(SearchMethod::exhaustive, {2, {1.0f, 2.0f}});
  EXPECT_THROW(search->nearest(std::vector<double>{1.0}), Error);
  EXPECT_THROW(search->nearest(std::vector<double>{1.0, INFINITY}), Error);
}

TEST(PrunedSearch, EqualsExhaustiveOnRandomTables) {
  for (const int dimension : {2, 12, 171}) {
    const NeighbourhoodTable table = table_with_duplicates(2000, dimension, 21 + dimension);
    const auto exhaustive = make_neighbourhood_search(SearchMethod::exhaustive, table);
    const auto pruned = make_neighbourhood_search(SearchMethod::pruned, table);
    const int count = 1000;
    const std::vector<double> queries = random_queries(count, dimension, 100 + dimension);
    std::vector<std::int64_t> expected(count);
    exhaustive->nearest_batch(queries, expected);
    for (int i = 0; i < count; ++i)
      ASSERT_EQ(pruned->nearest(query_at(queries, dimension, i)), expected[i])
          << "dimension " << dimension << " query " << i;
  }
}

TEST(PrunedSearch, EqualsExhaustiveAndBruteForceOnImageNeighbourhoods) {
  const int size = 64; // 4096 rows x 171, the Fig. 7 finest level's shape
  const NeighbourhoodTable table = image_table(size);
  const auto exhaustive = make_neighbourhood_search(SearchMethod::exhaustive, table);
  const auto pruned = make_neighbourhood_search(SearchMethod::pruned, table);
  const int count = 3000;
  const std::vector<double> queries = image_queries(table, size, count);
  std::vector<std::int64_t> expected(count);
  exhaustive->nearest_batch(queries, expected);
  std::int64_t checked = 0;
  const auto& lower_bounds = dynamic_cast<const PrunedSearch&>(*pruned);
  for (int i = 0; i < count; ++i) {
    const auto query = query_at(queries, 171, i);
    if (i % 10 == 0) {
      ASSERT_EQ(expected[i], brute_force(table, query)) << "query " << i;
    }
    ASSERT_EQ(pruned->nearest(query), expected[i]) << "query " << i;
    checked += static_cast<std::int64_t>(lower_bounds.candidates(query).size());
  }
  // The bounds prune: far fewer full distances than the exhaustive 4096 per query.
  EXPECT_LT(checked, std::int64_t{count} * table.rows() / 4);
}

TEST(TsvqSearch, OneLeafEqualsExhaustive) {
  const NeighbourhoodTable table = table_with_duplicates(500, 30, 31);
  const auto exhaustive = make_neighbourhood_search(SearchMethod::exhaustive, table);
  SearchOptions options;
  options.tsvq_leaf_size = table.rows();
  const auto tsvq = make_neighbourhood_search(SearchMethod::tsvq, table, options);
  EXPECT_EQ(dynamic_cast<const TsvqSearch&>(*tsvq).nodes().size(), 1u);
  const std::vector<double> queries = random_queries(500, 30, 32);
  for (int i = 0; i < 500; ++i) {
    const auto query = query_at(queries, 30, i);
    ASSERT_EQ(tsvq->nearest(query), exhaustive->nearest(query)) << "query " << i;
  }
}

TEST(TsvqSearch, FindsTheRightCluster) {
  // 8 cluster centres far apart (random in [0, 10)^d), 100 rows around each (+-0.05).
  const int dimension = 27, clusters = 8, per_cluster = 100;
  const CounterRng rng(41, 3);
  NeighbourhoodTable table{dimension, {}};
  std::vector<double> centres;
  for (int k = 0; k < clusters * dimension; ++k)
    centres.push_back(rng.uniform(0.0, 10.0, static_cast<std::uint64_t>(k), 0));
  // Rows interleaved (row r in cluster r % clusters), so cluster order is not row order.
  for (int r = 0; r < clusters * per_cluster; ++r)
    for (int c = 0; c < dimension; ++c)
      table.values.push_back(static_cast<float>(
          centres[(r % clusters) * dimension + c] +
          rng.uniform(-0.05, 0.05, static_cast<std::uint64_t>(r * dimension + c), 1)));
  const auto tsvq = make_neighbourhood_search(SearchMethod::tsvq, table);
  const auto& tree = dynamic_cast<const TsvqSearch&>(*tsvq);
  for (const auto& node : tree.nodes())
    if (node.left < 0) {
      EXPECT_EQ(node.count, 1) << "distinct rows end in leaves of one";
    }
  for (int i = 0; i < 400; ++i) {
    const int cluster = i % clusters;
    std::vector<double> query(dimension);
    for (int c = 0; c < dimension; ++c)
      query[c] = centres[cluster * dimension + c] +
                 rng.uniform(-0.05, 0.05, static_cast<std::uint64_t>(i * dimension + c), 2);
    EXPECT_EQ(tsvq->nearest(query) % clusters, cluster) << "query " << i;
  }
}

TEST(TsvqSearch, TreeIsAPartitionWithMeanCentroids) {
  const NeighbourhoodTable table = table_with_duplicates(600, 12, 51);
  const auto tsvq = make_neighbourhood_search(SearchMethod::tsvq, table);
  const auto& tree = dynamic_cast<const TsvqSearch&>(*tsvq);
  const auto& nodes = tree.nodes();
  const auto& order = tree.rows_in_order();
  std::vector<std::int64_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::int64_t r = 0; r < 600; ++r)
    ASSERT_EQ(sorted[r], r);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const auto& node = nodes[n];
    for (int c = 0; c < 12; ++c) { // centroid = mean of the node's rows
      double sum = 0.0;
      for (std::int64_t i = node.first; i < node.first + node.count; ++i)
        sum += table.values[order[i] * 12 + c];
      EXPECT_NEAR(tree.centroids()[n * 12 + c], sum / node.count, 1e-12);
    }
    if (node.left < 0) { // a leaf: one row, or duplicates of one row
      for (std::int64_t i = node.first + 1; i < node.first + node.count; ++i)
        EXPECT_EQ(
            tsvq->distance2(
                order[i], std::vector<double>(table.values.begin() + order[node.first] * 12,
                                              table.values.begin() + order[node.first] * 12 + 12)),
            0.0);
      continue;
    }
    EXPECT_EQ(nodes[node.left].first, node.first);
    EXPECT_EQ(nodes[node.left].count + nodes[node.right].count, node.count);
    EXPECT_GT(nodes[node.left].count, 0);
    EXPECT_GT(nodes[node.right].count, 0);
  }
  // Every row of the table, queried exactly, lands at distance 0 or close: TSVQ is approximate,
  // but most rows find themselves (or a duplicate).
  int found = 0;
  for (std::int64_t r = 0; r < 600; ++r) {
    const std::vector<double> query(table.values.begin() + r * 12,
                                    table.values.begin() + (r + 1) * 12);
    found += tsvq->distance2(tsvq->nearest(query), query) == 0.0;
  }
  EXPECT_GT(found, 600 * 9 / 10);
}

TEST(TsvqSearch, SameTreeEveryBuild) {
  const NeighbourhoodTable table = image_table(32);
  const auto first = make_neighbourhood_search(SearchMethod::tsvq, table);
  const auto second = make_neighbourhood_search(SearchMethod::tsvq, table);
  const auto& a = dynamic_cast<const TsvqSearch&>(*first);
  const auto& b = dynamic_cast<const TsvqSearch&>(*second);
  ASSERT_EQ(a.centroids().size(), b.centroids().size());
  EXPECT_EQ(std::memcmp(a.centroids().data(), b.centroids().data(),
                        a.centroids().size() * sizeof(double)),
            0);
  EXPECT_EQ(a.rows_in_order(), b.rows_in_order());
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  for (std::size_t n = 0; n < a.nodes().size(); ++n) {
    EXPECT_EQ(a.nodes()[n].left, b.nodes()[n].left);
    EXPECT_EQ(a.nodes()[n].count, b.nodes()[n].count);
  }
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
