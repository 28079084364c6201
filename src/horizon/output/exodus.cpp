#include "horizon/output/exodus.hpp"

#include <exodusII.h>

#include <cstring>
#include <filesystem>

#include "horizon/core/error.hpp"

namespace horizon {

namespace {

// Exodus's name arrays: a vector of C strings.
struct Names {
  std::vector<std::string> text;
  std::vector<char*> ptr;
  explicit Names(const std::vector<std::string>& names) : text(names) {
    for (auto& t : text) ptr.push_back(t.data());
  }
};

}  // namespace

ExodusWriter::ExodusWriter(const std::string& path, const ExodusLayout& layout) : path_(path), layout_(layout) {
  auto fail = [&](const std::string& what) { throw OutputError("cannot write the Exodus file '" + path_ + "': " + what); };
  if (layout_.points.size() != layout_.block.size()) fail("one block per point expected");
  const auto parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  members_.resize(layout_.block_names.size());
  for (std::size_t i = 0; i < layout_.block.size(); ++i) {
    const int b = layout_.block[i];
    if (b < 0 || static_cast<std::size_t>(b) >= members_.size()) fail("a point outside the listed blocks");
    members_[static_cast<std::size_t>(b)].push_back(i);
  }
  ex_opts(0);
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  id_ = ex_create(path.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  if (id_ < 0) fail("the Exodus library cannot create it");
  auto check = [&](int rc, const char* what) {
    if (rc < 0) fail(std::string(what) + " (Exodus error " + std::to_string(rc) + ")");
  };
  // Names up to 32 characters, as Peridigm's files (maximum_name_length = 32).
  ex_set_max_name_length(id_, 32);
  const auto n = static_cast<int64_t>(layout_.points.size());
  std::size_t blocks = 0;
  for (const auto& m : members_) blocks += m.empty() ? 0 : 1;
  check(ex_put_init(id_, layout_.title.c_str(), 3, n, n, static_cast<int64_t>(blocks), 0, 0), "the header");
  std::vector<double> x(layout_.points.size()), y(x.size()), z(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = layout_.points[i].x, y[i] = layout_.points[i].y, z[i] = layout_.points[i].z;
  check(ex_put_coord(id_, x.data(), y.data(), z.data()), "the coordinates");
  const char* coord_names[3] = {"x", "y", "z"};
  check(ex_put_coord_names(id_, const_cast<char**>(coord_names)), "the coordinate names");
  std::vector<int> elem_map;
  for (std::size_t b = 0; b < members_.size(); ++b) {
    if (members_[b].empty()) continue;
    const int id = static_cast<int>(b) + 1;
    check(ex_put_block(id_, EX_ELEM_BLOCK, id, "SPHERE", static_cast<int64_t>(members_[b].size()), 1, 0, 0, 0),
          "an element block");
    std::vector<int> conn;
    for (std::size_t i : members_[b]) conn.push_back(static_cast<int>(i) + 1), elem_map.push_back(static_cast<int>(i) + 1);
    check(ex_put_conn(id_, EX_ELEM_BLOCK, id, conn.data(), nullptr, nullptr), "the connectivity");
    check(ex_put_name(id_, EX_ELEM_BLOCK, id, layout_.block_names[b].c_str()), "a block name");
  }
  std::vector<int> node_map(layout_.points.size());
  for (std::size_t i = 0; i < node_map.size(); ++i) node_map[i] = static_cast<int>(i) + 1;
  check(ex_put_id_map(id_, EX_NODE_MAP, node_map.data()), "the node map");
  check(ex_put_id_map(id_, EX_ELEM_MAP, elem_map.data()), "the element map");
  const std::pair<ex_entity_type, const std::vector<std::string>*> kinds[3] = {
      {EX_NODAL, &layout_.nodal}, {EX_ELEM_BLOCK, &layout_.element}, {EX_GLOBAL, &layout_.global}};
  for (const auto& [type, names] : kinds) {
    if (names->empty()) continue;
    check(ex_put_variable_param(id_, type, static_cast<int>(names->size())), "the variable counts");
    Names nm(*names);
    check(ex_put_variable_names(id_, type, static_cast<int>(names->size()), nm.ptr.data()), "the variable names");
  }
  check(ex_update(id_), "the mesh");
}

ExodusWriter::~ExodusWriter() {
  if (id_ >= 0) ex_close(id_);
}

void ExodusWriter::append(const ExodusStep& step) {
  auto fail = [&](const std::string& what) { throw OutputError("cannot write the Exodus file '" + path_ + "': " + what); };
  if (step.nodal.size() != layout_.nodal.size() || step.element.size() != layout_.element.size() ||
      step.global.size() != layout_.global.size())
    fail("a frame's variables differ from the file's");
  const int k = steps_ + 1;
  auto check = [&](int rc, const char* what) {
    if (rc < 0) fail(std::string(what) + " of time step " + std::to_string(k) + " (Exodus error " + std::to_string(rc) + ")");
  };
  double t = step.time;
  check(ex_put_time(id_, k, &t), "the time");
  const auto n = static_cast<int64_t>(layout_.points.size());
  for (std::size_t v = 0; v < step.nodal.size(); ++v) {
    if (step.nodal[v].size() != layout_.points.size()) fail("a nodal variable of the wrong length");
    check(ex_put_var(id_, k, EX_NODAL, static_cast<int>(v) + 1, 1, n, step.nodal[v].data()), "a nodal variable");
  }
  std::vector<double> values;
  for (std::size_t v = 0; v < step.element.size(); ++v) {
    if (step.element[v].size() != layout_.points.size()) fail("an element variable of the wrong length");
    for (std::size_t b = 0; b < members_.size(); ++b) {
      if (members_[b].empty()) continue;
      values.clear();
      for (std::size_t i : members_[b]) values.push_back(step.element[v][i]);
      check(ex_put_var(id_, k, EX_ELEM_BLOCK, static_cast<int>(v) + 1, static_cast<int>(b) + 1,
                       static_cast<int64_t>(values.size()), values.data()),
            "an element variable");
    }
  }
  if (!step.global.empty())
    check(ex_put_var(id_, k, EX_GLOBAL, 1, 0, static_cast<int64_t>(step.global.size()), step.global.data()),
          "the global variables");
  check(ex_update(id_), "the flush");
  steps_ = k;
}

ExodusSeries read_exodus_series(const std::string& path) {
  auto fail = [&](const std::string& what) { throw OutputError("cannot read the Exodus file '" + path + "': " + what); };
  ex_opts(0);
  int cpu_ws = sizeof(double), io_ws = 0;
  float version = 0;
  const int id = ex_open(path.c_str(), EX_READ, &cpu_ws, &io_ws, &version);
  if (id < 0) fail("not an Exodus file");
  struct Closer {
    int id;
    ~Closer() { ex_close(id); }
  } closer{id};
  auto check = [&](int rc, const char* what) {
    if (rc < 0) fail(what);
  };
  ex_set_max_name_length(id, 32);
  ExodusSeries s;
  char title[MAX_LINE_LENGTH + 1] = {0};
  int ndim = 0, nnodes = 0, nelem = 0, nblk = 0, nns = 0, nss = 0;
  check(ex_get_init(id, title, &ndim, &nnodes, &nelem, &nblk, &nns, &nss), "the header");
  s.layout.title = title;
  std::vector<double> x(static_cast<std::size_t>(nnodes)), y(x.size()), z(x.size());
  check(ex_get_coord(id, x.data(), y.data(), z.data()), "the coordinates");
  for (std::size_t i = 0; i < x.size(); ++i) s.layout.points.push_back({x[i], y[i], z[i]});
  s.layout.block.assign(x.size(), -1);
  std::vector<int> ids(static_cast<std::size_t>(nblk));
  if (nblk) check(ex_get_ids(id, EX_ELEM_BLOCK, ids.data()), "the block ids");
  std::vector<std::vector<std::size_t>> members;
  for (int b : ids) {
    char type[MAX_STR_LENGTH + 1] = {0};
    int n = 0, npe = 0, ne = 0, nf = 0, na = 0;
    check(ex_get_block(id, EX_ELEM_BLOCK, b, type, &n, &npe, &ne, &nf, &na), "a block");
    if (npe != 1) fail("a block of " + std::to_string(npe) + "-node elements, not one-node SPHERE elements");
    std::vector<int> conn(static_cast<std::size_t>(n));
    if (n) check(ex_get_conn(id, EX_ELEM_BLOCK, b, conn.data(), nullptr, nullptr), "the connectivity");
    char name[40] = {0};
    ex_get_name(id, EX_ELEM_BLOCK, b, name);
    const int index = static_cast<int>(s.layout.block_names.size());
    s.layout.block_names.push_back(name);
    members.emplace_back();
    for (int c : conn) {
      if (c < 1 || c > nnodes) fail("a connectivity entry out of range");
      s.layout.block[static_cast<std::size_t>(c - 1)] = index;
      members.back().push_back(static_cast<std::size_t>(c - 1));
    }
  }
  const std::pair<ex_entity_type, std::vector<std::string>*> kinds[3] = {
      {EX_NODAL, &s.layout.nodal}, {EX_ELEM_BLOCK, &s.layout.element}, {EX_GLOBAL, &s.layout.global}};
  for (const auto& [type, names] : kinds) {
    int count = 0;
    check(ex_get_variable_param(id, type, &count), "the variable counts");
    std::vector<std::vector<char>> buf(static_cast<std::size_t>(count), std::vector<char>(40, 0));
    std::vector<char*> ptr;
    for (auto& b : buf) ptr.push_back(b.data());
    if (count) check(ex_get_variable_names(id, type, count, ptr.data()), "the variable names");
    for (auto& b : buf) names->push_back(b.data());
  }
  const int steps = ex_inquire_int(id, EX_INQ_TIME);
  for (int k = 1; k <= steps; ++k) {
    ExodusStep st;
    check(ex_get_time(id, k, &st.time), "a time");
    for (std::size_t v = 0; v < s.layout.nodal.size(); ++v) {
      st.nodal.emplace_back(x.size());
      check(ex_get_var(id, k, EX_NODAL, static_cast<int>(v) + 1, 1, nnodes, st.nodal.back().data()), "a nodal variable");
    }
    for (std::size_t v = 0; v < s.layout.element.size(); ++v) {
      st.element.emplace_back(x.size(), 0.0);
      for (std::size_t b = 0; b < ids.size(); ++b) {
        std::vector<double> values(members[b].size());
        if (values.empty()) continue;
        check(ex_get_var(id, k, EX_ELEM_BLOCK, static_cast<int>(v) + 1, ids[b], static_cast<int64_t>(values.size()),
                         values.data()),
              "an element variable");
        for (std::size_t e = 0; e < values.size(); ++e) st.element.back()[members[b][e]] = values[e];
      }
    }
    st.global.resize(s.layout.global.size());
    if (!st.global.empty())
      check(ex_get_var(id, k, EX_GLOBAL, 1, 0, static_cast<int64_t>(st.global.size()), st.global.data()),
            "the global variables");
    s.steps.push_back(std::move(st));
  }
  return s;
}

}  // namespace horizon
