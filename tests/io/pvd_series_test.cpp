// .pvd time series: what is written is read back by VTK's XML parser with exact times, in order;
// resume keeps entries up to the restart time; rewrites leave no temporary file behind.
#include "core/error.hpp"
#include "io/pvd_series.hpp"
#include "par/comm.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUtilities.h>

#include <fstream>

namespace texsim::io {
namespace {

/// (timestep, part, file) of every DataSet, parsed by VTK rather than by the code under test.
std::vector<PvdSeries::Entry> parse_with_vtk(const std::filesystem::path& path) {
  vtkSmartPointer<vtkXMLDataElement> root;
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(path.c_str()));
  EXPECT_TRUE(root);
  std::vector<PvdSeries::Entry> entries;
  if (!root)
    return entries;
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  for (int i = 0; collection && i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* dataset = collection->GetNestedElement(i);
    EXPECT_STREQ(dataset->GetName(), "DataSet");
    entries.push_back({std::stod(dataset->GetAttribute("timestep")),
                       std::stoi(dataset->GetAttribute("part")), dataset->GetAttribute("file")});
  }
  return entries;
}

void expect_entries(const std::vector<PvdSeries::Entry>& got,
                    const std::vector<PvdSeries::Entry>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].time, want[i].time) << i;
    EXPECT_EQ(got[i].part, want[i].part) << i;
    EXPECT_EQ(got[i].file, want[i].file) << i;
  }
}

TEST(PvdSeries, EntriesAreWrittenSortedWithExactTimes) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("pvd_write");
  PvdSeries series(comm, dir / "run.pvd");
  const double awkward = 0.1 + 0.2;
  series.add(awkward, "frames/b&c.pvtu");
  series.add(0.0, "frames/a.pvtu");
  series.add(0.0, "volume/a.vti", 1);
  series.add(awkward, "frames/b_again.pvtu");
  const std::vector<PvdSeries::Entry> want{
      {0.0, 0, "frames/a.pvtu"}, {0.0, 1, "volume/a.vti"}, {awkward, 0, "frames/b_again.pvtu"}};
  expect_entries(series.entries(), want);
  if (comm.is_root()) {
    expect_entries(parse_with_vtk(dir / "run.pvd"), want);
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(entry.path().filename(), "run.pvd") << "left behind: " << entry.path();
  }
  comm.barrier();
}

TEST(PvdSeries, ResumeDropsEntriesAfterTheRestartTime) {
  const auto comm = par::world();
  const auto path = test::scratch_dir("pvd_resume") / "run.pvd";
  {
    PvdSeries series(comm, path);
    for (int step = 0; step < 5; ++step)
      series.add(0.1 * step, "f_" + std::to_string(step) + " & more.vtu");
  }
  PvdSeries resumed = PvdSeries::resume(comm, path, 0.1 * 2);
  ASSERT_EQ(resumed.entries().size(), 3u);
  EXPECT_EQ(resumed.entries()[2].time, 0.1 * 2);
  EXPECT_EQ(resumed.entries()[2].file, "f_2 & more.vtu");
  resumed.add(0.1 * 3, "g_3.vtu");
  if (comm.is_root()) {
    const auto on_disk = parse_with_vtk(path);
    ASSERT_EQ(on_disk.size(), 4u);
    EXPECT_EQ(on_disk[1].time, 0.1);
    EXPECT_EQ(on_disk[3].file, "g_3.vtu");
  }
  comm.barrier();
  EXPECT_TRUE(PvdSeries::resume(comm, path.parent_path() / "absent.pvd", 1.0).entries().empty());
}

TEST(PvdSeries, AMalformedCollectionIsAnInputErrorNamingIt) {
  const auto comm = par::world();
  const auto path = test::scratch_dir("pvd_malformed") / "run.pvd";
  if (comm.is_root())
    std::ofstream(path) << "<VTKFile type=\"Collection\"><Collection>"
                           "<DataSet timestep=\"zero\" file=\"a.vtu\"/></Collection></VTKFile>";
  comm.barrier();
  try {
    PvdSeries::resume(comm, path, 1.0);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace texsim::io
