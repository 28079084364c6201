#include "horizon/geometry/gmsh_library.hpp"

#include <dlfcn.h>
#include <gmshc.h>
#include <omp.h>
#include <sys/resource.h>

#include <clocale>
#include <mutex>

#include "horizon/core/error.hpp"

#ifndef HORIZON_GMSH_LIBRARY
#define HORIZON_GMSH_LIBRARY "libgmsh.so"
#endif

namespace horizon::gmsh_library {

const char* library_name() { return HORIZON_GMSH_LIBRARY; }

namespace {

// The C API's functions, typed by gmshc.h's own declarations.
struct Api {
  decltype(&::gmshFree) free;
  decltype(&::gmshInitialize) initialize;
  decltype(&::gmshFinalize) finalize;
  decltype(&::gmshMerge) merge;
  decltype(&::gmshOptionSetNumber) set_number;
  decltype(&::gmshModelGetEntities) get_entities;
  decltype(&::gmshModelGetPhysicalGroupsForEntity) physical_groups_for_entity;
  decltype(&::gmshModelGetPhysicalName) physical_name;
  decltype(&::gmshModelMeshGetNodes) get_nodes;
  decltype(&::gmshModelMeshGetElements) get_elements;
  decltype(&::gmshModelMeshGetElementProperties) element_properties;
  decltype(&::gmshLoggerGetLastError) last_error;
  decltype(&::gmshOptionGetNumber) get_number;
  decltype(&::gmshModelAdd) model_add;
  decltype(&::gmshModelRemove) model_remove;
  decltype(&::gmshModelGetCurrent) model_get_current;
  decltype(&::gmshModelSetCurrent) model_set_current;
  // Gmsh 4.9 and later: whether someone else (a Python program importing the same
  // library) holds a session; absent from Debian 12's Gmsh 4.8.
  int (*is_initialized)(int*) = nullptr;
};

template <class F>
void resolve(void* lib, F& f, const char* name) {
  f = reinterpret_cast<F>(dlsym(lib, name));
  if (!f) throw Error(std::string("the Gmsh library ") + library_name() + " has no function " + name);
}

// Loaded once per process; never unloaded (OpenCASCADE's static objects do not survive
// dlclose).
void* library_handle = nullptr;

const Api& api() {
  static std::once_flag once;
  static Api a{};
  static std::string failure;
  std::call_once(once, [] {
    void* lib = dlopen(library_name(), RTLD_NOW | RTLD_LOCAL);
    library_handle = lib;
    if (!lib) {
      const char* why = dlerror();
      failure = std::string("cannot load the Gmsh library ") + library_name() + " (" + (why ? why : "?") +
                "): install Debian's libgmsh-dev (scripts/install-deps.sh)";
      return;
    }
    try {
      resolve(lib, a.free, "gmshFree");
      resolve(lib, a.initialize, "gmshInitialize");
      resolve(lib, a.finalize, "gmshFinalize");
      resolve(lib, a.merge, "gmshMerge");
      resolve(lib, a.set_number, "gmshOptionSetNumber");
      resolve(lib, a.get_entities, "gmshModelGetEntities");
      resolve(lib, a.physical_groups_for_entity, "gmshModelGetPhysicalGroupsForEntity");
      resolve(lib, a.physical_name, "gmshModelGetPhysicalName");
      resolve(lib, a.get_nodes, "gmshModelMeshGetNodes");
      resolve(lib, a.get_elements, "gmshModelMeshGetElements");
      resolve(lib, a.element_properties, "gmshModelMeshGetElementProperties");
      resolve(lib, a.last_error, "gmshLoggerGetLastError");
      resolve(lib, a.get_number, "gmshOptionGetNumber");
      resolve(lib, a.model_add, "gmshModelAdd");
      resolve(lib, a.model_remove, "gmshModelRemove");
      resolve(lib, a.model_get_current, "gmshModelGetCurrent");
      resolve(lib, a.model_set_current, "gmshModelSetCurrent");
      a.is_initialized = reinterpret_cast<int (*)(int*)>(dlsym(lib, "gmshIsInitialized"));
    } catch (const Error& e) {
      failure = e.what();
    }
  });
  if (!failure.empty()) throw Error(failure);
  return a;
}

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

// Gmsh's last error message, or `what` when it has none.
std::string last_error(const Api& a, const char* what) {
  char* text = nullptr;
  int ierr = 0;
  a.last_error(&text, &ierr);
  std::string s = text ? text : "";
  if (text) a.free(text);
  return s.empty() ? std::string("Gmsh failed in ") + what : s;
}

void check(const Api& a, int ierr, const char* what) {
  if (ierr != 0) throw Error(last_error(a, what));
}

// Copies a Gmsh-allocated array and frees it.
template <class T>
std::vector<T> take(const Api& a, T* p, std::size_t n) {
  std::vector<T> v(p, p + n);
  if (p) a.free(p);
  return v;
}

}  // namespace

void* symbol(const char* name) {
  api();
  void* f = dlsym(library_handle, name);
  if (!f) throw Error(std::string("the Gmsh library ") + library_name() + " has no function " + name);
  return f;
}

struct Session::State {
  std::unique_lock<std::mutex> lock;
  std::string locale;
  rlimit stack{};
  bool have_stack = false;
  int threads = 1;
  int levels = 1;
  int dynamic = 0;
  // A session someone else opened (Gmsh >= 4.9 tells): Horizon works in a model of its
  // own, then removes it and puts back their current model and terminal setting.
  bool borrowed = false;
  std::string their_model;
  double their_terminal = 0;
};

Session::Session() : saved_(nullptr) {
  const Api& a = api();
  auto* s = new State;
  s->lock = std::unique_lock<std::mutex>(gmsh_mutex());
  if (const char* l = std::setlocale(LC_ALL, nullptr)) s->locale = l;
  s->have_stack = getrlimit(RLIMIT_STACK, &s->stack) == 0;
  s->threads = omp_get_max_threads();
  s->levels = omp_get_max_active_levels();
  s->dynamic = omp_get_dynamic();
  saved_ = s;
  int ierr = 0;
  s->borrowed = a.is_initialized && a.is_initialized(&ierr) == 1 && ierr == 0;
  if (s->borrowed) {
    char* name = nullptr;
    a.model_get_current(&name, &ierr);
    if (name) s->their_model = name, a.free(name);
    a.get_number("General.Terminal", &s->their_terminal, &ierr);
    a.model_add("horizon", &ierr);
  } else {
    a.initialize(0, nullptr, 0, &ierr);  // no gmshrc, no options files
  }
  if (ierr == 0) a.set_number("General.Terminal", 0, &ierr);
  if (ierr != 0) {
    const std::string message = last_error(a, "gmshInitialize");
    end();
    throw Error(message);
  }
}

Session::~Session() { end(); }

void Session::end() {
  if (!saved_) return;
  const Api& a = api();
  State* s = saved_;
  int ierr = 0;
  if (s->borrowed) {
    a.model_remove(&ierr);
    if (!s->their_model.empty()) a.model_set_current(s->their_model.c_str(), &ierr);
    a.set_number("General.Terminal", s->their_terminal, &ierr);
  } else {
    a.finalize(&ierr);
  }
  if (!s->locale.empty()) std::setlocale(LC_ALL, s->locale.c_str());
  if (s->have_stack) setrlimit(RLIMIT_STACK, &s->stack);
  omp_set_num_threads(s->threads);
  omp_set_max_active_levels(s->levels);
  omp_set_dynamic(s->dynamic);
  saved_ = nullptr;
  delete s;  // releases the lock last
}

std::string Session::merge(const std::string& path) {
  const Api& a = api();
  int ierr = 0;
  a.merge(path.c_str(), &ierr);
  return ierr == 0 ? std::string() : last_error(a, "gmshMerge");
}

void Session::set_number(const char* option, double value) {
  const Api& a = api();
  int ierr = 0;
  a.set_number(option, value, &ierr);
  check(a, ierr, option);
}

std::vector<std::pair<int, int>> Session::entities(int dim) {
  const Api& a = api();
  int* dim_tags = nullptr;
  std::size_t n = 0;
  int ierr = 0;
  a.get_entities(&dim_tags, &n, dim, &ierr);
  const auto flat = take(a, dim_tags, n);
  check(a, ierr, "gmshModelGetEntities");
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i + 1 < flat.size(); i += 2) out.emplace_back(flat[i], flat[i + 1]);
  return out;
}

std::vector<int> Session::physical_groups_of(int dim, int tag) {
  const Api& a = api();
  int* tags = nullptr;
  std::size_t n = 0;
  int ierr = 0;
  a.physical_groups_for_entity(dim, tag, &tags, &n, &ierr);
  auto out = take(a, tags, n);
  check(a, ierr, "gmshModelGetPhysicalGroupsForEntity");
  return out;
}

std::string Session::physical_name(int dim, int tag) {
  const Api& a = api();
  char* name = nullptr;
  int ierr = 0;
  a.physical_name(dim, tag, &name, &ierr);
  std::string out = name ? name : "";
  if (name) a.free(name);
  check(a, ierr, "gmshModelGetPhysicalName");
  return out;
}

void Session::nodes(std::vector<std::size_t>& tags, std::vector<double>& xyz) {
  const Api& a = api();
  std::size_t* t = nullptr;
  double* c = nullptr;
  double* u = nullptr;
  std::size_t nt = 0, nc = 0, nu = 0;
  int ierr = 0;
  a.get_nodes(&t, &nt, &c, &nc, &u, &nu, -1, -1, 0, 0, &ierr);
  tags = take(a, t, nt);
  xyz = take(a, c, nc);
  take(a, u, nu);
  check(a, ierr, "gmshModelMeshGetNodes");
  if (xyz.size() != 3 * tags.size()) throw Error("Gmsh returned " + std::to_string(xyz.size()) + " coordinates for " + std::to_string(tags.size()) + " nodes");
}

std::vector<ElementBlock> Session::elements(int dim, int tag) {
  const Api& a = api();
  int* types = nullptr;
  std::size_t ntypes = 0;
  std::size_t** etags = nullptr;
  std::size_t* etags_n = nullptr;
  std::size_t etags_nn = 0;
  std::size_t** ntags = nullptr;
  std::size_t* ntags_n = nullptr;
  std::size_t ntags_nn = 0;
  int ierr = 0;
  a.get_elements(&types, &ntypes, &etags, &etags_n, &etags_nn, &ntags, &ntags_n, &ntags_nn, dim, tag, &ierr);
  std::vector<ElementBlock> out(ntypes);
  for (std::size_t i = 0; i < ntypes; ++i) {
    out[i].type = types[i];
    if (i < etags_nn) out[i].tags = take(a, etags[i], etags_n[i]);
    if (i < ntags_nn) out[i].nodes = take(a, ntags[i], ntags_n[i]);
  }
  for (std::size_t i = ntypes; i < etags_nn; ++i) a.free(etags[i]);
  for (std::size_t i = ntypes; i < ntags_nn; ++i) a.free(ntags[i]);
  for (void* p : {static_cast<void*>(types), static_cast<void*>(etags), static_cast<void*>(etags_n),
                  static_cast<void*>(ntags), static_cast<void*>(ntags_n)})
    if (p) a.free(p);
  check(a, ierr, "gmshModelMeshGetElements");
  for (auto& b : out) {
    char* name = nullptr;
    double* local = nullptr;
    std::size_t nlocal = 0;
    a.element_properties(b.type, &name, &b.dim, &b.order, &b.nodes_per_element, &local, &nlocal, &b.primary_nodes,
                         &ierr);
    b.name = name ? name : "";
    if (name) a.free(name);
    take(a, local, nlocal);
    check(a, ierr, "gmshModelMeshGetElementProperties");
    if (b.nodes_per_element <= 0 || b.nodes.size() != b.tags.size() * static_cast<std::size_t>(b.nodes_per_element))
      throw Error("Gmsh returned " + std::to_string(b.nodes.size()) + " node tags for " + std::to_string(b.tags.size()) +
                  " elements of type " + b.name);
  }
  return out;
}

}  // namespace horizon::gmsh_library
