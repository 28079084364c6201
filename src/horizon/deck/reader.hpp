#pragma once
// The schema toolkit of the deck reader: typed reads of YAML nodes that fail with a
// DeckError naming file:line:column, the key path, what was expected and what was found.
// Nothing outside src/horizon/deck includes this header.
#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "horizon/core/expression.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/geometry/mesh.hpp"

namespace horizon::deck {

// What every read needs to know: the deck's name (for messages), its dimension (how
// many components a vector has) and where warnings go.
struct DeckContext {
  std::string file;
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;
  std::vector<std::string>* warnings = nullptr;
  double thickness = 1;  // 2-D: a mesh's element areas become volumes with it
  // Mesh files read so far (bodies and regions often name the same one), by path.
  std::shared_ptr<std::map<std::string, std::shared_ptr<const Mesh>>> meshes =
      std::make_shared<std::map<std::string, std::shared_ptr<const Mesh>>>();
  // Components of a load or motion vector (read_vector_expr): 3 for thin structures, whose
  // nodes move in 3-D space; 0 means the dimension.
  int motion_components = 0;
  bool structure = false;  // a beam, plate or shell (Config::structure)
  bool cylinder = false;   // a shell wrapped around a cylinder: 2-D boxes reach through z

  [[noreturn]] void fail(const YAML::Mark& at, const std::string& message) const;
  void warn(const YAML::Mark& at, const std::string& message) const;
};

// A node of the deck, the key path that leads to it (`materials.glass.density`,
// `loads[1].velocity[0]`) and where a message about it should point.
struct Item {
  YAML::Node node;
  std::string path;
  YAML::Mark mark;                     // the value; its key when the value is empty
  std::optional<YAML::Mark> key_mark;  // the key, for values of a map
};

std::string child_path(const std::string& path, std::string_view key);
std::string index_path(const std::string& path, std::size_t index);
// "a map", "a list", "an empty value", "'abc'": what was found, for messages.
std::string describe(const YAML::Node& node);
[[noreturn]] void fail_expected(const DeckContext& ctx, const Item& item, std::string_view expected);

// One key of a map as written: its text, where the key is, and its value.
struct Entry {
  std::string key;
  Item value;
};

// The entries of a map in deck order; an empty value counts as an empty map.
// Duplicate keys are errors.
std::vector<Entry> map_entries(const DeckContext& ctx, const Item& item);

// A map whose keys must all come from a fixed list. Unknown keys are errors that
// suggest the closest valid key.
class MapReader {
 public:
  MapReader(const DeckContext& ctx, const Item& item, std::vector<std::string> allowed);

  const Item& self() const { return item_; }
  bool has(std::string_view key) const { return find(key).has_value(); }
  std::optional<Item> find(std::string_view key) const;
  // A required key; `what` says what it is for the message when it is missing.
  Item get(std::string_view key, std::string_view what) const;
  [[noreturn]] void fail_missing(std::string_view key, std::string_view what) const;
  // Fails when more than one of `keys` is present (pointing at the second) and, if
  // `required`, when none is. Returns the one present, if any.
  std::optional<std::string> exactly_one(const std::vector<std::string>& keys, bool required) const;

 private:
  const DeckContext& ctx_;
  Item item_;
  std::vector<Entry> entries_;
};

// Scalars. Numbers must be finite; a quoted number is accepted.
double read_number(const DeckContext& ctx, const Item& item);
double read_positive(const DeckContext& ctx, const Item& item);      // > 0
double read_non_negative(const DeckContext& ctx, const Item& item);  // >= 0
int read_int(const DeckContext& ctx, const Item& item);
bool read_bool(const DeckContext& ctx, const Item& item);
std::string read_string(const DeckContext& ctx, const Item& item);
// The scalar's text as written, for "found ..." in messages.
std::string text_of(const Item& item);

// One of a fixed set of words; the error lists them and suggests the closest.
template <class E>
E read_enum(const DeckContext& ctx, const Item& item, const std::vector<std::pair<std::string, E>>& choices);
// The index in `valid` of the word the scalar names.
std::size_t choose_word(const DeckContext& ctx, const Item& item, const std::vector<std::string>& valid);
[[noreturn]] void fail_choice(const DeckContext& ctx, const Item& item, const std::string& found,
                              const std::vector<std::string>& valid, std::string_view what);

// A name that must be one of `valid` (a material, a region): the error lists them.
void check_reference(const DeckContext& ctx, const Item& item, const std::string& name,
                     const std::vector<std::string>& valid, std::string_view what, std::string_view note = "");

// Lists; an empty value counts as an empty list.
std::vector<Item> read_list(const DeckContext& ctx, const Item& item);

// A point or direction with one component per dimension; the others are zero.
Vec3 read_vector(const DeckContext& ctx, const Item& item);
// A vector whose components are numbers, expressions in t, x, y, z, or (if `allow_free`)
// null for "not prescribed". Components beyond the dimension are unset, or zero when
// free components are not allowed. Thin structures (ctx.motion_components = 3) take
// three components in any dimension.
Vec3Expr read_vector_expr(const DeckContext& ctx, const Item& item, bool allow_free);
// One number or expression in t, x, y, z.
Expression read_scalar_expr(const DeckContext& ctx, const Item& item);

template <class E>
E read_enum(const DeckContext& ctx, const Item& item, const std::vector<std::pair<std::string, E>>& choices) {
  std::vector<std::string> valid;
  for (const auto& choice : choices) valid.push_back(choice.first);
  return choices[choose_word(ctx, item, valid)].second;
}

}  // namespace horizon::deck
