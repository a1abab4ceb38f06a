// tests/support/vtu_check.hpp -- a VTU file as VTK itself reads it: runs tests/vtu_dump.py (VTK's
// vtkXMLUnstructuredGridReader, Debian python3-vtk9, installed by scripts/install-deps.sh) and
// parses its canonical text, so that tests compare what VTK sees with what they wrote.
#pragma once

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace tetia::testvtu {

struct VtkArray {
  std::string type;            ///< VTK's name: double, long_long, unsigned_char, ...
  std::vector<double> values;  ///< exact for Float64 and for integers below 2^53
};

struct VtkView {
  bool ok = false;
  std::string error;
  std::vector<std::array<double, 3>> points;
  std::vector<int> cell_types;
  std::vector<std::vector<long long>> cells;
  std::vector<std::pair<std::string, VtkArray>> point_arrays, cell_arrays;  ///< in file order
  const VtkArray* cell_array(const std::string& name) const {
    for (const auto& [n, a] : cell_arrays)
      if (n == name) return &a;
    return nullptr;
  }
  const VtkArray* point_array(const std::string& name) const {
    for (const auto& [n, a] : point_arrays)
      if (n == name) return &a;
    return nullptr;
  }
};

// vtu_dump.py's array names: %20 is a space, %25 a percent sign.
inline std::string unescape(const std::string& in) {
  std::string out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] == '%' && in.compare(i, 3, "%20") == 0) {
      out += ' ';
      i += 2;
    } else if (in[i] == '%' && in.compare(i, 3, "%25") == 0) {
      out += '%';
      i += 2;
    } else {
      out += in[i];
    }
  }
  return out;
}

inline VtkView read_with_vtk(const std::filesystem::path& file) {
  VtkView v;
  const std::filesystem::path script = std::filesystem::path(__FILE__).parent_path().parent_path() / "vtu_dump.py";
  const std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" + file.string() + "' 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
  if (!pipe) {
    v.error = "cannot run " + cmd;
    return v;
  }
  std::string text;
  char buf[1 << 16];
  for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, pipe.get())) > 0;) text.append(buf, got);
  const int status = ::pclose(pipe.release());
  if (status != 0) {
    v.error = "vtu_dump.py failed (is python3-vtk9 installed? scripts/install-deps.sh): " + text.substr(0, 2000);
    return v;
  }
  std::istringstream in(text);
  std::string word;
  std::size_t n = 0;
  in >> word >> n;
  v.points.resize(n);
  for (auto& p : v.points) in >> p[0] >> p[1] >> p[2];
  in >> word >> n;
  v.cells.resize(n);
  v.cell_types.resize(n);
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t k = 0;
    in >> v.cell_types[c] >> k;
    v.cells[c].resize(k);
    for (auto& id : v.cells[c]) in >> id;
  }
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string kind, name;
    VtkArray a;
    ls >> kind >> name >> a.type;
    name = unescape(name);
    for (std::string t; ls >> t;) a.values.push_back(std::strtod(t.c_str(), nullptr));
    (kind == "point_array" ? v.point_arrays : v.cell_arrays).emplace_back(name, std::move(a));
  }
  v.ok = static_cast<bool>(in) || in.eof();
  return v;
}

// The values of the DataArray named `name` in an ASCII VTU that tetia wrote (--ascii: each
// value the shortest text that reads back as the same double), read without VTK, which costs a
// Python start per file: for tests that compare many outputs of tetia's own with each other.
// *found is false where the file has no such array.
inline std::vector<double> tetia_ascii_array(const std::filesystem::path& file, const std::string& name, bool* found) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<double> values;
  const std::size_t at = text.find("Name=\"" + name + "\"");
  *found = at != std::string::npos;
  if (!*found) return values;
  const std::size_t begin = text.find('>', at) + 1, end = text.find("</DataArray>", begin);
  std::istringstream body(text.substr(begin, end - begin));
  for (std::string t; body >> t;) values.push_back(std::strtod(t.c_str(), nullptr));
  return values;
}

}  // namespace tetia::testvtu
