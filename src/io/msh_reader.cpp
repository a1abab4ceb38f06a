// src/io/msh_reader.cpp -- parse_msh (msh_reader.hpp): Gmsh's .msh 2.x and 4.1, ASCII and binary.
//
// The formats (Gmsh reference manual, "MSH file format", versions 2.2 and 4.1): sections
// "$Name" ... "$EndName"; $MeshFormat ("version file-type data-size", then in binary files
// the integer 1 to give the byte order); $Nodes and $Elements, whose layouts differ between 2.x
// (one list) and 4.1 (blocks per entity; binary counts and tags as size_t); $NodeData and
// $ElementData, alike in both (text headers of string, real and integer tags, then "tag
// values..." per entry, binary: a 4-byte tag and the doubles); $ElementNodeData the same with
// each entry's number of nodes after its tag (binary: a 4-byte int) and that many nodes' values
// (Gmsh writes an entry to a line, as this reader requires). Every other section is skipped
// up to its end marker ($Entities of a binary 4.1 file is parsed, being binary).
//
// Every number goes through one checked conversion (std::from_chars); every count is compared
// with the bytes left before it sizes anything, and every section must end exactly where its
// counts say. Offsets of lines and records are kept so that errors can name the line (counted
// only when an error is reported) or the byte offset.
#include "msh_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace tetia::detail {

int msh_nodes_per_element(int type) {
  // Gmsh's element types 1-31, 92 and 93 (the ones its manual lists).
  static constexpr int kNodes[32] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1,
                                     8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56};
  if (type >= 1 && type <= 31) return kNodes[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

namespace {

// The first-order type of a higher-order cell (Gmsh lists the corners first, in the first-order
// element's order): tetrahedra 11, 29-31; triangles 9, 20-25; hexahedra 12, 17, 92, 93; prisms
// 13, 18; pyramids 14, 19; quadrilaterals 10, 16. 0 for any other type.
int corner_type_of(int type) {
  if (type == 11 || (type >= 29 && type <= 31)) return 4;
  if (type == 9 || (type >= 20 && type <= 25)) return 2;
  if (type == 12 || type == 17 || type == 92 || type == 93) return 5;
  if (type == 13 || type == 18) return 6;
  if (type == 14 || type == 19) return 7;
  if (type == 10 || type == 16) return 3;
  return 0;
}

// Tags are kept as int64 (TetMesh::node_tags): larger ones are refused.
constexpr std::uint64_t kMaxTag = std::numeric_limits<std::int64_t>::max();

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// What a number is, for an error message: "node 17: coordinate". Held as views and made into a
// string only when an error is reported, so that reading a node or an element builds no string.
struct What {
  std::string_view text;
  std::uint64_t tag = 0;  // 0: none
  std::string_view suffix;
  What(const char* t) : text(t) {}              // NOLINT: implicit on purpose
  What(const std::string& t) : text(t) {}       // NOLINT
  What(std::string_view t, std::uint64_t g, std::string_view s) : text(t), tag(g), suffix(s) {}
  std::string str() const {
    std::string out(text);
    if (tag != 0) out += ' ' + std::to_string(tag);
    out += suffix;
    return out;
  }
};

class Parser {
 public:
  Parser(std::string_view bytes, const std::string& name, MshFile& out) : b_(bytes), name_(name), out_(out) {
    out_.bytes = bytes;
  }

  void run() {
    header();
    bool nodes = false, elements = false;
    // A file may hold several meshes one after the other (each from its own $MeshFormat; Gmsh
    // appends the mesh again with every view it writes to a file): see the $Nodes case for how
    // 2.x and 4.1 files differ there. Data sections accumulate.
    while (true) {
      skip_blank();
      if (pos_ >= b_.size()) break;
      const std::size_t at = pos_;
      const std::string_view line = next_line("a section");
      if (line.empty() || line[0] != '$') fail(at, "expected a section ($Name), found \"" + shorten(line) + "\"");
      const std::string_view section = line.substr(1);
      if (section == "MeshFormat") {
        pos_ = at;
        header();
        ++segment_;
      } else if (section == "Nodes" || (section == "ParametricNodes" && out_.major == 2)) {
        // A 2.x file that holds a mesh again (Gmsh writes it with every view it appends, and
        // with Mesh.SaveAll renumbered differently): the last copy is the mesh, as Gmsh's 2.2
        // reader has it. In 4.1 copies are merged and must agree (msh_mesh.hpp).
        if (out_.major == 2 && nodes_segment_ >= 0 && nodes_segment_ != segment_) {
          out_.node_tags.clear();
          out_.xyz.clear();
          out_.node_where.clear();
        }
        nodes_segment_ = segment_;
        nodes = true;
        out_.major == 2 ? nodes2(section == "ParametricNodes") : nodes4();
        end_of(std::string(section));
      } else if (section == "Elements") {
        if (out_.major == 2 && elements_segment_ >= 0 && elements_segment_ != segment_) {
          for (MshCells* c : {&out_.tetrahedra, &out_.triangles, &out_.hexahedra, &out_.prisms, &out_.pyramids,
                              &out_.quadrangles, &out_.higher_tetrahedra, &out_.higher_triangles,
                              &out_.higher_hexahedra, &out_.higher_prisms, &out_.higher_pyramids,
                              &out_.higher_quadrangles})
            *c = MshCells{};
          other_tags_.clear();
          out_.higher_order_3d = out_.higher_order_2d = 0;
        }
        elements_segment_ = segment_;
        elements = true;
        out_.major == 2 ? elements2() : elements4();
        end_of("Elements");
      } else if (section == "NodeData" || section == "ElementData" || section == "ElementNodeData") {
        data(section == "NodeData" ? DataKind::nodes : section == "ElementData" ? DataKind::elements
                                                                                 : DataKind::element_nodes);
        end_of(std::string(section));
      } else if (section == "Entities" && out_.binary && out_.major == 4) {
        entities4();
        end_of("Entities");
      } else if (section.starts_with("End")) {
        fail(at, "\"" + shorten(line) + "\" without its section");
      } else {
        skip_section(std::string(section), at);
      }
    }
    if (!nodes) fail(b_.size(), "no $Nodes section");
    if (!elements) fail(b_.size(), "no $Elements section");
    // Elements not kept, each counted once (a mesh given twice in a 4.1 file lists them twice).
    std::sort(other_tags_.begin(), other_tags_.end());
    out_.other_elements = static_cast<std::size_t>(std::unique(other_tags_.begin(), other_tags_.end()) - other_tags_.begin());
  }

 private:
  // --- errors ---------------------------------------------------------------------------------

  [[noreturn]] void fail(std::size_t where, const std::string& what) const {
    throw std::runtime_error("tetia: " + name_ + ": " + out_.location(where) + ": " + what);
  }

  static std::string shorten(std::string_view s) {
    std::string out;
    for (const char c : s.substr(0, 40)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    if (s.size() > 40) out += "...";
    return out;
  }

  // --- lines and tokens (ASCII) ---------------------------------------------------------------

  // Whitespace and empty lines between sections.
  void skip_blank() {
    while (pos_ < b_.size() && (is_space(b_[pos_]) || b_[pos_] == '\n')) ++pos_;
  }

  // The next line without its end (\n or \r\n) and trailing blanks; `what` names what was
  // expected, for the error at the end of the file. line_at_ is the line's offset.
  std::string_view next_line(const char* what) {
    if (pos_ >= b_.size()) fail(pos_, std::string("unexpected end of file (expected ") + what + ")");
    line_at_ = pos_;
    const std::size_t end = b_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? b_.size() : end;
    std::string_view line = b_.substr(pos_, stop - pos_);
    pos_ = end == std::string_view::npos ? b_.size() : end + 1;
    while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
    while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
    return line;
  }

  // Splits a line into at most kMax tokens; fails with `what` if there are more.
  struct Tokens {
    static constexpr int kMax = 160;  // an element line: tag, type, tags, up to 125 nodes
    std::string_view t[kMax];
    int n = 0;
  };
  void split(std::string_view line, Tokens& tk, const char* what) const {
    tk.n = 0;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && !is_space(line[j])) ++j;
      if (tk.n == Tokens::kMax) fail(line_at_, std::string("too many numbers on a line (") + what + ")");
      tk.t[tk.n++] = line.substr(i, j - i);
      i = j;
    }
  }

  // A leading '+' is read as Gmsh's strtod/fscanf read it (from_chars does not take it).
  static std::string_view unplus(std::string_view s) {
    return s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+' ? s.substr(1) : s;
  }

  template <class Int>
  Int to_int(std::string_view s_in, const What& what) const {
    const std::string_view s = unplus(s_in);
    Int v{};
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size())
      fail(line_at_, what.str() + ": \"" + shorten(s) + "\" is not " +
                         (std::is_signed_v<Int> ? "an integer" : "a non-negative integer") + " in range");
    return v;
  }
  double to_double(std::string_view s_in, const What& what) const {
    const std::string_view s = unplus(s_in);
    double v = 0.0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec == std::errc::result_out_of_range && r.ptr == s.data() + s.size() && s.size() < 64) {
      // Beyond the double range: a magnitude below the smallest subnormal reads as strtod
      // reads it (0 or the nearest subnormal, as Gmsh has it); one above the largest double is
      // not finite, an error below.
      const std::string copy(s);
      v = std::strtod(copy.c_str(), nullptr);
      if (!std::isfinite(v)) fail(line_at_, what.str() + ": \"" + shorten(s) + "\" is not a number in range");
    } else if (r.ec != std::errc() || r.ptr != s.data() + s.size()) {
      fail(line_at_, what.str() + ": \"" + shorten(s) + "\" is not a number in range");
    }
    if (!std::isfinite(v)) fail(line_at_, what.str() + ": \"" + shorten(s) + "\" is not finite");
    return v;
  }
  std::uint64_t to_tag(std::string_view s, const What& what) const {
    const auto v = to_int<std::uint64_t>(s, what);
    if (v == 0) fail(line_at_, what.str() + ": tag 0 (tags start at 1)");
    if (v > kMaxTag) fail(line_at_, what.str() + ": tag " + std::to_string(v) + " beyond 2^63 - 1");
    return v;
  }

  // A line of exactly `count` tokens.
  void line_of(Tokens& tk, int count, const char* what) {
    split(next_line(what), tk, what);
    if (tk.n != count)
      fail(line_at_, std::string(what) + ": " + std::to_string(count) + " numbers expected, found " +
                         std::to_string(tk.n));
  }

  // A count that needs at least `min_bytes` bytes per item from here on.
  void check_count(std::uint64_t count, std::size_t min_bytes, std::size_t at, const char* what) const {
    const std::size_t left = b_.size() - std::min(pos_, b_.size());
    if (count > left / min_bytes)
      fail(at, "the file declares " + std::to_string(count) + " " + what + ", more than its remaining " +
                   std::to_string(left) + " bytes can hold");
  }

  // --- binary records -------------------------------------------------------------------------

  template <class T>
  T raw(const What& what) {
    if (pos_ > b_.size() || b_.size() - pos_ < sizeof(T))
      fail(pos_, "unexpected end of file (in " + what.str() + ")");
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint64_t raw_tag(bool size_t_tag, const What& what) {
    const std::size_t at = pos_;
    std::uint64_t v = 0;
    if (size_t_tag) {
      v = raw<std::uint64_t>(what);
    } else {
      const std::int32_t t = raw<std::int32_t>(what);
      if (t < 0) fail(at, what.str() + ": negative tag " + std::to_string(t));
      v = static_cast<std::uint64_t>(t);
    }
    if (v == 0) fail(at, what.str() + ": tag 0 (tags start at 1)");
    if (v > kMaxTag) fail(at, what.str() + ": tag " + std::to_string(v) + " beyond 2^63 - 1");
    return v;
  }
  double raw_double(const What& what) {
    const std::size_t at = pos_;
    const double v = raw<double>(what);
    if (!std::isfinite(v)) fail(at, what.str() + ": not finite");
    return v;
  }
  std::int32_t raw_int(const char* what) { return raw<std::int32_t>(what); }
  std::uint64_t raw_size(const char* what) { return raw<std::uint64_t>(what); }

  // --- sections -------------------------------------------------------------------------------

  void header() {
    skip_blank();
    if (pos_ >= b_.size() || b_.substr(pos_, 11) != "$MeshFormat")
      fail(pos_, "not a Gmsh mesh file (no $MeshFormat header)");
    next_line("$MeshFormat");
    const std::string_view format = next_line("the format line");
    const std::size_t format_at = line_at_;
    Tokens tk;
    split(format, tk, "the format line");
    if (tk.n != 3) fail(format_at, "the format line must be \"version file-type data-size\"");
    if (tk.t[0] == "4.1") {
      out_.major = 4;
    } else if (tk.t[0] == "2.2" || tk.t[0] == "2.1" || tk.t[0] == "2" || tk.t[0] == "2.0") {
      out_.major = 2;
    } else {
      fail(format_at, "version " + shorten(tk.t[0]) +
                          " is not supported (2.x and 4.1 are; convert with gmsh FILE -save -format msh41)");
    }
    const int type = to_int<int>(tk.t[1], "file type");
    if (type != 0 && type != 1) fail(format_at, "file type must be 0 (ASCII) or 1 (binary)");
    if (to_int<int>(tk.t[2], "data size") != 8) fail(format_at, "data size must be 8 (doubles)");
    out_.binary = type == 1;
    out_.formats.emplace_back(pos_, out_.binary);
    if (out_.binary) {
      const std::size_t at = pos_;
      const std::int32_t one = raw_int("the byte order");
      if (one != 1)
        fail(at, one == 0x01000000 ? "a big-endian binary file (not supported)" : "no byte-order mark (the integer 1)");
      // The rest of that line.
      while (pos_ < b_.size() && is_space(b_[pos_])) ++pos_;
      if (pos_ < b_.size() && b_[pos_] == '\n') ++pos_;
    }
    const std::string_view end = next_line("$EndMeshFormat");
    if (end != "$EndMeshFormat") fail(line_at_, "expected $EndMeshFormat, found \"" + shorten(end) + "\"");
  }

  void end_of(const std::string& section) {
    skip_blank();
    const std::string marker = "$End" + section;
    const std::string_view line = next_line(marker.c_str());
    if (line != marker)
      fail(line_at_, "expected " + marker + " after the counted data, found \"" + shorten(line) +
                         "\" (a count that disagrees with the data?)");
  }

  // An unknown or unused section: up to its end marker. ASCII: line by line; binary: the first
  // occurrence of "$EndName" at the start of a line (as Gmsh does).
  void skip_section(const std::string& section, std::size_t at) {
    const std::string marker = "$End" + section;
    if (!out_.binary) {
      while (pos_ < b_.size())
        if (next_line(marker.c_str()) == marker) return;
    } else {
      for (std::size_t p = b_.find(marker, pos_); p != std::string_view::npos; p = b_.find(marker, p + 1))
        if (p == 0 || b_[p - 1] == '\n') {
          pos_ = p;
          next_line(marker.c_str());
          return;
        }
    }
    fail(at, "section $" + shorten(section) + " has no " + shorten(marker));
  }

  void add_node(std::uint64_t tag, const double* p, std::size_t at) {
    out_.node_tags.push_back(tag);
    out_.xyz.insert(out_.xyz.end(), p, p + 3);
    out_.node_where.push_back(at);
  }

  // 2.x: "N", then N lines "tag x y z" (binary: int tag, 3 doubles).
  // $ParametricNodes (2.x, Mesh.SaveParametric): "tag x y z dim entity" and dim parameters
  // (none for dim 0 or 3), read for the coordinates; binary: int tag, 3 doubles, int dim, int
  // entity, the parameters as doubles.
  void nodes2(bool parametric) {
    Tokens tk;
    line_of(tk, 1, "the number of nodes");
    const std::size_t count_at = line_at_;
    const auto n = to_int<std::uint64_t>(tk.t[0], "the number of nodes");
    check_count(n, out_.binary ? 28 : 8, count_at, "nodes");
    reserve_nodes(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      double p[3];
      if (out_.binary) {
        const std::size_t at = pos_;
        const std::uint64_t tag = raw_tag(false, "node");
        for (double& c : p) c = raw_double(What("node", tag, ": coordinate"));
        if (parametric) {
          const std::int32_t dim = raw_int("a parametric node's dimension");
          raw_int("a parametric node's entity");
          if (dim < 0 || dim > 3) fail(at, "node " + std::to_string(tag) + ": parametric dimension " + std::to_string(dim));
          for (int k = 0; k < (dim == 1 ? 1 : dim == 2 ? 2 : 0); ++k) raw<double>("a node's parameter");
        }
        add_node(tag, p, at);
      } else {
        if (parametric) {
          split(next_line("a parametric node line"), tk, "a parametric node line");
          if (tk.n < 6) fail(line_at_, "a parametric node line needs tag x y z dim entity");
          const int dim = to_int<int>(tk.t[4], "a parametric node's dimension");
          const int params = dim == 1 ? 1 : dim == 2 ? 2 : 0;
          if (dim < 0 || dim > 3 || tk.n != 6 + params)
            fail(line_at_, "a parametric node line of dimension " + std::to_string(dim) + " needs " +
                               std::to_string(6 + params) + " numbers, found " + std::to_string(tk.n));
        } else {
          line_of(tk, 4, "a node line (tag x y z)");
        }
        const std::uint64_t tag = to_tag(tk.t[0], "node");
        for (int k = 0; k < 3; ++k) p[k] = to_double(tk.t[k + 1], What("node", tag, ": coordinate"));
        add_node(tag, p, line_at_);
      }
    }
  }

  // 4.1: "blocks nodes min-tag max-tag", then per block "dim entity parametric count", the
  // count tags, then the count coordinate lines "x y z" (plus dim parameters if parametric).
  // Binary: the same numbers, counts and tags as size_t, dim/entity/parametric as int.
  void nodes4() {
    Tokens tk;
    std::uint64_t blocks = 0, total = 0;
    const std::size_t header_at = pos_;
    if (out_.binary) {
      blocks = raw_size("the $Nodes header");
      total = raw_size("the $Nodes header");
      raw_size("the $Nodes header");
      raw_size("the $Nodes header");
    } else {
      line_of(tk, 4, "the $Nodes header (blocks nodes min-tag max-tag)");
      blocks = to_int<std::uint64_t>(tk.t[0], "the number of node blocks");
      total = to_int<std::uint64_t>(tk.t[1], "the number of nodes");
    }
    check_count(blocks, out_.binary ? 20 : 8, header_at, "node blocks");
    check_count(total, out_.binary ? 32 : 8, header_at, "nodes");
    reserve_nodes(total);
    std::uint64_t seen = 0;
    std::vector<std::uint64_t> tags;
    std::vector<std::size_t> where;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::size_t block_at = pos_;
      int dim = 0, parametric = 0;
      std::uint64_t count = 0;
      if (out_.binary) {
        dim = raw_int("a node block header");
        raw_int("a node block header");
        parametric = raw_int("a node block header");
        count = raw_size("a node block header");
      } else {
        line_of(tk, 4, "a node block header (dim entity parametric count)");
        dim = to_int<int>(tk.t[0], "a node block's dimension");
        parametric = to_int<int>(tk.t[2], "a node block's parametric flag");
        count = to_int<std::uint64_t>(tk.t[3], "a node block's count");
      }
      if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1))
        fail(out_.binary ? block_at : line_at_, "a node block's dimension (0-3) or parametric flag (0, 1) is invalid");
      if (count > total - seen)
        fail(out_.binary ? block_at : line_at_, "node blocks hold more nodes than the " + std::to_string(total) +
                                                     " the header declares");
      seen += count;
      const int per_node = 3 + (parametric ? dim : 0);
      check_count(count, out_.binary ? 8 + 8 * static_cast<std::size_t>(per_node) : 4, block_at, "nodes in a block");
      tags.clear();
      where.clear();
      for (std::uint64_t i = 0; i < count; ++i) {
        if (out_.binary) {
          where.push_back(pos_);
          tags.push_back(raw_tag(true, "node"));
        } else {
          line_of(tk, 1, "a node tag");
          where.push_back(line_at_);
          tags.push_back(to_tag(tk.t[0], "node"));
        }
      }
      for (std::uint64_t i = 0; i < count; ++i) {
        double p[3 + 3];
        const What what("node", tags[i], ": coordinate");
        if (out_.binary) {
          for (int k = 0; k < per_node; ++k) p[k] = raw_double(what);
        } else {
          line_of(tk, per_node, "a node's coordinates");
          for (int k = 0; k < per_node; ++k) p[k] = to_double(tk.t[k], what);
        }
        add_node(tags[i], p, where[i]);
      }
    }
    if (seen != total)
      fail(header_at, "the $Nodes header declares " + std::to_string(total) + " nodes, its blocks hold " +
                          std::to_string(seen));
  }

  void reserve_nodes(std::uint64_t n) {  // n was checked against the bytes left
    out_.node_tags.reserve(out_.node_tags.size() + n);
    out_.node_where.reserve(out_.node_where.size() + n);
    out_.xyz.reserve(out_.xyz.size() + 3 * n);
  }

  // One element: kept (tetrahedra, triangles, hexahedra, prisms, pyramids, quadrangles) or
  // counted.
  void add_element(int type, std::uint64_t tag, const std::uint64_t* nodes, std::size_t at) {
    MshCells* cells = type == 4   ? &out_.tetrahedra
                      : type == 2 ? &out_.triangles
                      : type == 5 ? &out_.hexahedra
                      : type == 6 ? &out_.prisms
                      : type == 7 ? &out_.pyramids
                      : type == 3 ? &out_.quadrangles
                                  : nullptr;
    if (cells == nullptr) {
      other_tags_.push_back(tag);
      const int corners = corner_type_of(type);
      if (corners == 0) return;
      const bool volume = corners >= 4;
      out_.higher_order_3d += volume;
      out_.higher_order_2d += !volume;
      cells = corners == 4   ? &out_.higher_tetrahedra
              : corners == 2 ? &out_.higher_triangles
              : corners == 5 ? &out_.higher_hexahedra
              : corners == 6 ? &out_.higher_prisms
              : corners == 7 ? &out_.higher_pyramids
                             : &out_.higher_quadrangles;
      cells->tags.push_back(tag);
      cells->nodes.insert(cells->nodes.end(), nodes, nodes + msh_nodes_per_element(corners));  // the corners come first
      cells->where.push_back(at);
      cells->types.push_back(static_cast<std::uint8_t>(type));  // corner_type_of knows types <= 93 only
      return;
    }
    cells->tags.push_back(tag);
    cells->nodes.insert(cells->nodes.end(), nodes, nodes + msh_nodes_per_element(type));
    cells->where.push_back(at);
  }

  std::string element_what(std::uint64_t tag) const { return "element " + std::to_string(tag); }

  // 2.x: "M", then M lines "tag type ntags tags... nodes..."; binary: blocks of a header (int
  // type, int count, int ntags) and count records of ints (tag, tags, nodes).
  void elements2() {
    Tokens tk;
    line_of(tk, 1, "the number of elements");
    const std::size_t count_at = line_at_;
    const auto m = to_int<std::uint64_t>(tk.t[0], "the number of elements");
    check_count(m, 8, count_at, "elements");
    std::uint64_t nodes[128];
    if (out_.binary) {
      std::uint64_t read = 0;
      while (read < m) {
        const std::size_t at = pos_;
        const int type = raw_int("an element block header");
        const std::int32_t count = raw_int("an element block header");
        const std::int32_t ntags = raw_int("an element block header");
        const int nv = msh_nodes_per_element(type);
        if (nv == 0) fail(at, "element type " + std::to_string(type) + " is unknown (its size is needed to read on)");
        if (count <= 0 || static_cast<std::uint64_t>(count) > m - read || ntags < 0 || ntags > 1000)
          fail(at, "an element block header (type " + std::to_string(type) + ", " + std::to_string(count) +
                       " elements, " + std::to_string(ntags) + " tags) does not fit the " + std::to_string(m) +
                       " elements declared");
        check_count(static_cast<std::uint64_t>(count), 4 * (1 + static_cast<std::size_t>(ntags) + nv), at, "elements");
        for (std::int32_t e = 0; e < count; ++e) {
          const std::size_t rec = pos_;
          const std::uint64_t tag = raw_tag(false, "element");
          pos_ += 4 * static_cast<std::size_t>(ntags);  // fits: check_count
          for (int k = 0; k < nv; ++k) nodes[k] = raw_tag(false, What("element", tag, ": node"));
          add_element(type, tag, nodes, rec);
        }
        read += static_cast<std::uint64_t>(count);
      }
      return;
    }
    for (std::uint64_t e = 0; e < m; ++e) {
      split(next_line("an element line"), tk, "an element line");
      if (tk.n < 3) fail(line_at_, "an element line needs at least tag, type and number of tags");
      const std::uint64_t tag = to_tag(tk.t[0], "element");
      const int type = to_int<int>(tk.t[1], What("element", tag, ": type"));
      const int ntags = to_int<int>(tk.t[2], What("element", tag, ": number of tags"));
      const int nv = msh_nodes_per_element(type);
      if (ntags < 0 || ntags > tk.n - 3) fail(line_at_, element_what(tag) + ": more tags declared than given");
      if (nv == 0) {  // unknown type: the line says how long it is
        other_tags_.push_back(tag);
        continue;
      }
      if (tk.n != 3 + ntags + nv)
        fail(line_at_, element_what(tag) + ": type " + std::to_string(type) + " has " + std::to_string(nv) +
                           " nodes, the line gives " + std::to_string(tk.n - 3 - ntags));
      for (int k = 0; k < nv; ++k) nodes[k] = to_tag(tk.t[3 + ntags + k], What("element", tag, ": node"));
      add_element(type, tag, nodes, line_at_);
    }
  }

  // 4.1: "blocks elements min-tag max-tag", per block "dim entity type count" and count lines
  // "tag nodes..."; binary: counts and tags as size_t, dim/entity/type as int.
  void elements4() {
    Tokens tk;
    std::uint64_t blocks = 0, total = 0;
    const std::size_t header_at = pos_;
    if (out_.binary) {
      blocks = raw_size("the $Elements header");
      total = raw_size("the $Elements header");
      raw_size("the $Elements header");
      raw_size("the $Elements header");
    } else {
      line_of(tk, 4, "the $Elements header (blocks elements min-tag max-tag)");
      blocks = to_int<std::uint64_t>(tk.t[0], "the number of element blocks");
      total = to_int<std::uint64_t>(tk.t[1], "the number of elements");
    }
    check_count(blocks, out_.binary ? 20 : 8, header_at, "element blocks");
    check_count(total, out_.binary ? 16 : 4, header_at, "elements");
    std::uint64_t seen = 0;
    std::uint64_t nodes[128];
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::size_t block_at = pos_;
      int type = 0;
      std::uint64_t count = 0;
      if (out_.binary) {
        raw_int("an element block header");
        raw_int("an element block header");
        type = raw_int("an element block header");
        count = raw_size("an element block header");
      } else {
        line_of(tk, 4, "an element block header (dim entity type count)");
        type = to_int<int>(tk.t[2], "an element block's type");
        count = to_int<std::uint64_t>(tk.t[3], "an element block's count");
      }
      const std::size_t at = out_.binary ? block_at : line_at_;
      if (count > total - seen)
        fail(at, "element blocks hold more elements than the " + std::to_string(total) + " the header declares");
      seen += count;
      const int nv = msh_nodes_per_element(type);
      if (out_.binary) {
        if (nv == 0) fail(at, "element type " + std::to_string(type) + " is unknown (its size is needed to read on)");
        check_count(count, 8 * (1 + static_cast<std::size_t>(nv)), at, "elements in a block");
        for (std::uint64_t e = 0; e < count; ++e) {
          const std::size_t rec = pos_;
          const std::uint64_t tag = raw_tag(true, "element");
          for (int k = 0; k < nv; ++k) nodes[k] = raw_tag(true, What("element", tag, ": node"));
          add_element(type, tag, nodes, rec);
        }
        continue;
      }
      check_count(count, 4, at, "elements in a block");
      for (std::uint64_t e = 0; e < count; ++e) {
        split(next_line("an element line"), tk, "an element line");
        if (tk.n < 1) fail(line_at_, "an empty element line");
        const std::uint64_t tag = to_tag(tk.t[0], "element");
        if (nv == 0) {
          other_tags_.push_back(tag);
          continue;
        }
        if (tk.n != 1 + nv)
          fail(line_at_, element_what(tag) + ": type " + std::to_string(type) + " has " + std::to_string(nv) +
                             " nodes, the line gives " + std::to_string(tk.n - 1));
        for (int k = 0; k < nv; ++k) nodes[k] = to_tag(tk.t[1 + k], What("element", tag, ": node"));
        add_element(type, tag, nodes, line_at_);
      }
    }
    if (seen != total)
      fail(header_at, "the $Elements header declares " + std::to_string(total) + " elements, its blocks hold " +
                          std::to_string(seen));
  }

  // Binary 4.1 $Entities: counts of points, curves, surfaces, volumes (size_t); a point is an int
  // tag, 3 doubles, size_t n and n int physical tags; the others an int tag, 6 doubles, size_t n,
  // n ints, size_t m, m ints (bounding entities). Read only to be skipped exactly.
  void entities4() {
    std::uint64_t counts[4];
    const std::size_t at = pos_;
    for (auto& c : counts) c = raw_size("the $Entities header");
    for (int d = 0; d < 4; ++d) {
      check_count(counts[d], d == 0 ? 36 : 68, at, "entities");
      for (std::uint64_t i = 0; i < counts[d]; ++i) {
        raw_int("an entity");
        for (int k = 0; k < (d == 0 ? 3 : 6); ++k) raw<double>("an entity");
        for (int list = 0; list < (d == 0 ? 1 : 2); ++list) {
          const std::size_t n_at = pos_;
          const std::uint64_t n = raw_size("an entity");
          check_count(n, 4, n_at, "tags of an entity");
          pos_ += 4 * n;
        }
      }
    }
  }

  enum class DataKind { nodes, elements, element_nodes };

  // The next token of `line` from `i` on (empty at its end): for the lines of $ElementNodeData,
  // whose length the file chooses (an element's nodes times the components), not bounded as
  // Tokens is.
  static std::string_view next_token(std::string_view line, std::size_t& i) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t from = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    return line.substr(from, i - from);
  }

  // $NodeData / $ElementData / $ElementNodeData: string tags (the first is the name), real tags
  // (the first is the time), integer tags (step, components, count, [partition]), then count
  // entries, "tag values..." ($ElementNodeData: "tag nodes values...", the values node after
  // node, each node's components in a row; binary: a 4-byte tag, a 4-byte node count, the
  // doubles).
  void data(DataKind kind) {
    Tokens tk;
    MshData d;
    d.on_elements = kind == DataKind::elements;
    d.on_element_nodes = kind == DataKind::element_nodes;
    line_of(tk, 1, "the number of string tags");
    const int nstrings = to_int<int>(tk.t[0], "the number of string tags");
    if (nstrings < 0 || nstrings > 100) fail(line_at_, "the number of string tags is out of range");
    for (int i = 0; i < nstrings; ++i) {
      std::string_view s = next_line("a string tag");
      if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
      if (i == 0) d.name = std::string(s);
    }
    line_of(tk, 1, "the number of real tags");
    const int nreals = to_int<int>(tk.t[0], "the number of real tags");
    if (nreals < 0 || nreals > 100) fail(line_at_, "the number of real tags is out of range");
    for (int i = 0; i < nreals; ++i) {
      line_of(tk, 1, "a real tag");
      to_double(tk.t[0], "a real tag");
    }
    line_of(tk, 1, "the number of integer tags");
    const int nints = to_int<int>(tk.t[0], "the number of integer tags");
    if (nints < 3 || nints > 100)
      fail(line_at_, "a data section needs at least 3 integer tags (step, components, count)");
    std::int64_t ints[3] = {0, 0, 0};
    for (int i = 0; i < nints; ++i) {
      line_of(tk, 1, "an integer tag");
      const auto v = to_int<std::int64_t>(tk.t[0], "an integer tag");
      if (i < 3) ints[i] = v;
    }
    const std::string field = "field " + (d.name.empty() ? std::string("(unnamed)") : d.name);
    d.step = ints[0];
    if (ints[1] < 1 || ints[1] > 9) fail(line_at_, field + ": " + std::to_string(ints[1]) + " components (1 to 9 are valid)");
    d.components = static_cast<int>(ints[1]);
    if (ints[2] < 0) fail(line_at_, field + ": a negative number of values");
    const auto n = static_cast<std::uint64_t>(ints[2]);
    const std::size_t nc = static_cast<std::size_t>(d.components);
    const bool per_node = kind == DataKind::element_nodes;
    // The least an entry takes: its tag (and node count) and one node's values.
    const std::size_t ints_per_entry = per_node ? 2 : 1;
    check_count(n, out_.binary ? 4 * ints_per_entry + 8 * nc : 2 * (ints_per_entry + nc), line_at_, "data entries");
    d.tags.reserve(n);
    d.where.reserve(n);
    d.values.reserve(n * nc);
    if (per_node) d.nodes.reserve(n);
    const char* entity = kind == DataKind::nodes ? "node" : "element";
    const std::string field_kind = field + ": " + entity, value_at = field + ": the value at " + entity;
    for (std::uint64_t i = 0; i < n; ++i) {
      if (per_node) {
        element_node_entry(d, field_kind, value_at);
      } else if (out_.binary) {
        d.where.push_back(pos_);
        const std::uint64_t tag = raw_tag(false, field_kind);
        d.tags.push_back(tag);
        for (std::size_t k = 0; k < nc; ++k)
          d.values.push_back(raw_double(What(value_at, tag, "")));
      } else {
        line_of(tk, 1 + d.components, "a data line (tag and values)");
        d.where.push_back(line_at_);
        const std::uint64_t tag = to_tag(tk.t[0], field_kind);
        d.tags.push_back(tag);
        for (std::size_t k = 0; k < nc; ++k)
          d.values.push_back(to_double(tk.t[1 + k], What(value_at, tag, "")));
      }
    }
    out_.data.push_back(std::move(d));
  }

  // One entry of $ElementNodeData into `d`: the tag, the number of nodes (at least 1; whether
  // it is the element's is checked where the mesh is assembled, which knows the elements) and
  // that many nodes' values, no more and no fewer (ASCII: on one line).
  void element_node_entry(MshData& d, const std::string& field_kind, const std::string& value_at) {
    const auto nc = static_cast<std::uint64_t>(d.components);
    const auto bad_count = [&](std::size_t at, std::uint64_t tag, std::int64_t count) {
      fail(at, field_kind + " " + std::to_string(tag) + ": " + std::to_string(count) +
                   " nodes (an element has at least 1)");
    };
    if (out_.binary) {
      const std::size_t at = pos_;
      d.where.push_back(at);
      const std::uint64_t tag = raw_tag(false, field_kind);
      const std::int32_t count = raw_int("an element's number of nodes");
      if (count < 1) bad_count(at, tag, count);
      const std::uint64_t want = static_cast<std::uint64_t>(count) * nc;  // < 2^35
      check_count(want, 8, at, "values of an element");
      d.tags.push_back(tag);
      d.nodes.push_back(static_cast<std::uint32_t>(count));
      const What what(value_at, tag, "");
      for (std::uint64_t k = 0; k < want; ++k) d.values.push_back(raw_double(what));
      return;
    }
    const std::string_view line = next_line("a data line (tag, number of nodes and values)");
    d.where.push_back(line_at_);
    std::size_t i = 0;
    const std::string_view tag_text = next_token(line, i), count_text = next_token(line, i);
    if (count_text.empty()) fail(line_at_, "a data line needs the tag, the number of nodes and the values");
    const std::uint64_t tag = to_tag(tag_text, field_kind);
    const auto count = to_int<std::int32_t>(count_text, What(field_kind, tag, ": number of nodes"));
    if (count < 1) bad_count(line_at_, tag, count);
    const std::uint64_t want = static_cast<std::uint64_t>(count) * nc;
    std::uint64_t got = 0;
    const What what(value_at, tag, "");
    // At most `want` values are kept; the rest of the line is only counted, for the message.
    for (std::string_view t = next_token(line, i); !t.empty(); t = next_token(line, i), ++got)
      if (got < want) d.values.push_back(to_double(t, what));
    if (got != want)
      fail(line_at_, field_kind + " " + std::to_string(tag) + ": " + std::to_string(count) + " nodes of " +
                         std::to_string(nc) + (nc == 1 ? " component" : " components") + " need " +
                         std::to_string(want) + " values, the line gives " + std::to_string(got));
    d.tags.push_back(tag);
    d.nodes.push_back(static_cast<std::uint32_t>(count));
  }

  std::string_view b_;
  const std::string& name_;
  MshFile& out_;
  std::size_t pos_ = 0;
  std::size_t line_at_ = 0;
  int segment_ = 0;  // how many $MeshFormat headers so far (a file may hold several meshes)
  int nodes_segment_ = -1, elements_segment_ = -1;
  std::vector<std::uint64_t> other_tags_;  // tags of the elements not kept
};

}  // namespace

std::string MshFile::location(std::size_t where) const {
  where = std::min(where, bytes.size());
  bool in_binary = false;
  for (const auto& [from, is_binary] : formats)
    if (from <= where) in_binary = is_binary;
  if (in_binary) return "byte offset " + std::to_string(where);
  const auto lines = std::count(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(where), '\n');
  return "line " + std::to_string(lines + 1);
}

MshFile parse_msh(std::string_view bytes, const std::string& name) {
  MshFile out;
  Parser(bytes, name, out).run();
  return out;
}

std::string read_file_bytes(const std::filesystem::path& file, const std::string& name) {
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(st)) throw std::runtime_error("tetia: " + name + ": cannot open: no such file");
  if (std::filesystem::is_directory(st)) throw std::runtime_error("tetia: " + name + ": cannot open: is a directory");
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error("tetia: " + name + ": cannot open: " + std::strerror(errno));
  std::string bytes;
  // A regular file is read into a string of its size in one call, rather than appended 64 KB at
  // a time (which copies the text again at each reallocation). Whatever else there is (a pipe,
  // or a file that grew meanwhile) is appended.
  if (std::filesystem::is_regular_file(st)) {
    const auto size = std::filesystem::file_size(file, ec);
    if (!ec) {
      bytes.resize(static_cast<std::size_t>(size));
      bytes.resize(std::fread(bytes.data(), 1, bytes.size(), f));
    }
  }
  char buf[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, got);
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  if (bad) throw std::runtime_error("tetia: " + name + ": read error");
  return bytes;
}

}  // namespace tetia::detail
