#include "io/pvd_series.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "io/xml_escape.hpp"
#include "par/collective.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace texsim::io {

std::string step_name(std::int64_t step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%09lld", static_cast<long long>(step));
  return name;
}
namespace {

/// Shortest text that reads back as exactly `value`.
std::string exact_text(double value) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  return std::string(buffer, end);
}

std::string xml_unescape(const std::string& text) {
  static const std::map<std::string, char> entities{
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string plain;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto end = text.find(';', i);
    const auto entity = text[i] == '&' && end != std::string::npos
                            ? entities.find(text.substr(i, end - i + 1))
                            : entities.end();
    if (entity == entities.end()) {
      plain += text[i];
      continue;
    }
    plain += entity->second;
    i = end;
  }
  return plain;
}

/// The DataSet entries of a collection written by PvdSeries (attributes in double quotes).
std::vector<PvdSeries::Entry> parse_collection(const std::string& xml,
                                               const std::filesystem::path& path) {
  if (xml.find("type=\"Collection\"") == std::string::npos)
    TEXSIM_INPUT_ERROR(path.string() << ": not a ParaView collection (no VTKFile "
                                        "type=\"Collection\")");
  static const std::regex dataset(R"(<DataSet\s([^>]*)>)");
  static const std::regex attribute(R"re((\w+)\s*=\s*"([^"]*)")re");
  std::vector<PvdSeries::Entry> entries;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), dataset);
       it != std::sregex_iterator(); ++it) {
    std::map<std::string, std::string> values;
    const std::string attributes = (*it)[1];
    for (auto a = std::sregex_iterator(attributes.begin(), attributes.end(), attribute);
         a != std::sregex_iterator(); ++a)
      values[(*a)[1]] = xml_unescape((*a)[2]);
    PvdSeries::Entry entry{0.0, 0, values["file"]};
    const std::string& time = values["timestep"];
    const std::string part = values.contains("part") ? values["part"] : "0";
    const auto time_parse = std::from_chars(time.data(), time.data() + time.size(), entry.time);
    const auto part_parse = std::from_chars(part.data(), part.data() + part.size(), entry.part);
    if (entry.file.empty() || time_parse.ec != std::errc() ||
        time_parse.ptr != time.data() + time.size() || part_parse.ec != std::errc())
      TEXSIM_INPUT_ERROR(path.string() << ": malformed DataSet entry '" << (*it)[0]
                                       << "', expected timestep=\"<number>\" part=\"<int>\" "
                                          "file=\"<path>\"");
    entries.push_back(entry);
  }
  return entries;
}

/// The file's text read on rank 0 and broadcast; empty if it does not exist.
std::string read_on_root(const par::Comm& comm, const std::filesystem::path& path) {
  std::string text;
  par::run_collectively(comm, [&] {
    if (!comm.is_root() || !std::filesystem::exists(path))
      return;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream contents;
    contents << in.rdbuf();
    TEXSIM_VERIFY(in, path.string() << ": cannot read");
    text = contents.str();
  });
  auto length = static_cast<unsigned long long>(text.size());
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, comm.raw);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm.raw);
  return text;
}

bool earlier(const PvdSeries::Entry& a, const PvdSeries::Entry& b) {
  return a.time < b.time || (a.time == b.time && a.part < b.part);
}

} // namespace

PvdSeries::PvdSeries(const par::Comm& comm, std::filesystem::path path)
    : PvdSeries(comm, std::move(path), {}) {}

PvdSeries::PvdSeries(const par::Comm& comm, std::filesystem::path path, std::vector<Entry> entries)
    : comm_(comm), path_(std::move(path)), entries_(std::move(entries)) {
  std::sort(entries_.begin(), entries_.end(), earlier);
  rewrite();
}

std::vector<PvdSeries::Entry> PvdSeries::read_entries(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    TEXSIM_INPUT_ERROR(path.string() << ": cannot open the ParaView collection (.pvd)");
  std::ostringstream contents;
  contents << in.rdbuf();
  return parse_collection(contents.str(), path);
}

PvdSeries PvdSeries::resume(const par::Comm& comm, std::filesystem::path path,
                            double restart_time) {
  const std::string xml = read_on_root(comm, path);
  std::vector<Entry> entries;
  par::run_collectively(comm, [&] {
    if (!xml.empty())
      entries = parse_collection(xml, path);
  });
  std::erase_if(entries, [&](const Entry& entry) { return entry.time > restart_time; });
  return PvdSeries(comm, std::move(path), std::move(entries));
}

void PvdSeries::add(double time, const std::string& relative_file, int part) {
  const Entry entry{time, part, relative_file};
  const auto position = std::lower_bound(entries_.begin(), entries_.end(), entry, earlier);
  if (position != entries_.end() && position->time == time && position->part == part)
    *position = entry;
  else
    entries_.insert(position, entry);
  rewrite();
}

void PvdSeries::rewrite() const {
  par::run_collectively(comm_, [&] {
    if (!comm_.is_root())
      return;
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (const auto& entry : entries_)
      xml << "    <DataSet timestep=\"" << exact_text(entry.time) << "\" group=\"\" part=\""
          << entry.part << "\" file=\"" << xml_escape(entry.file) << "\"/>\n";
    xml << "  </Collection>\n"
        << "</VTKFile>\n";
    write_atomically(path_, xml.str());
  });
}

} // namespace texsim::io
