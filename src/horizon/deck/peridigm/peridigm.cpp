#include "horizon/deck/peridigm/peridigm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "horizon/core/error.hpp"
#include "horizon/core/expression.hpp"
#include "horizon/deck/exodus_variables.hpp"
#include "horizon/deck/peridigm/exodus_discretization.hpp"
#include "horizon/deck/peridigm/function_string.hpp"
#include "horizon/deck/peridigm/sections.hpp"
#include "horizon/deck/reader.hpp"
#include "horizon/deck/suggest.hpp"

namespace horizon::peridigm {

namespace {

using namespace horizon::deck;
namespace fs = std::filesystem;

// Peridigm compares type words without case, spaces or underscores
// (Peridigm_Enums.cpp, survey sec. 1.6).
std::string squash(const std::string& s) {
  std::string r;
  for (char c : s)
    if (c != ' ' && c != '_') r += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

struct Point {
  Vec3 x;
  double volume = 0;
  int block = 1;
};

struct Translation {
  const DeckContext& ctx;
  fs::path folder;
  std::vector<Point> points;  // in Peridigm's global id order (id = index + 1)
  double horizon = 0;  // the blocks' (with several, the group's being read, then the largest)
  YAML::Node out;
  std::optional<Item> horizon_item;
  bool several_horizons = false;  // block groups of different horizons, or one that varies in space
  // Diffusion materials (read_material): the first one's Material Model item, and whether
  // they ask for the improved quadrature (every one alike: it is the thermal section's).
  std::optional<Item> diffusion_item;
  std::optional<bool> improved_quadrature;
  std::optional<Item> mechanical_item;  // the first material with mechanics
  // The deck's top-level Enable Bond-Associated Hypoelastic Model (Elastic Hypoelastic
  // Correspondence's bond-associated form): false when absent.
  bool bond_associated_hypoelastic = false;
  std::string influence = "constant";  // the Discretization's Influence Function, mapped
};

// Numbers as their shortest exact decimal text (reads back to the same double).
YAML::Node number(double v) { return YAML::Node(fmt::format("{}", v)); }

YAML::Node point_row(const Vec3& x, std::optional<double> volume) {
  YAML::Node row(YAML::NodeType::Sequence);
  row.SetStyle(YAML::EmitterStyle::Flow);
  row.push_back(number(x.x));
  row.push_back(number(x.y));
  row.push_back(number(x.z));
  if (volume) row.push_back(number(*volume));
  return row;
}

// Whether the text is a number alone (spaces around it allowed), as strtod reads one.
bool whole_number_text(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  std::strtod(begin, &end);
  if (end == begin) return false;
  while (*end == ' ' || *end == '\t') ++end;
  return *end == '\0';
}

// A value that may be a number or a string holding one.
double value_number(const DeckContext& ctx, const Item& item) { return read_number(ctx, item); }

// --- Discretization --------------------------------------------------------------

void read_text_file(Translation& t, const Item& file_item) {
  const fs::path path = resolve_deck_file(t.folder.string(), read_string(t.ctx, file_item));
  std::ifstream in(path);
  if (!in) t.ctx.fail(file_item.mark, file_item.path + ": cannot open the text-file discretisation '" + path.string() + "'");
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    // Peridigm_TextFileDiscretization.cpp: rows starting with #, / or * are comments.
    if (first == std::string::npos || line[first] == '#' || line[first] == '/' || line[first] == '*') continue;
    std::istringstream row(line);
    std::vector<double> v;
    std::string word;
    while (row >> word) {
      char* end = nullptr;
      const double x = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' || !std::isfinite(x))
        t.ctx.fail(file_item.mark,
                   fmt::format("{}: {}:{}: expected a number, found '{}'", file_item.path, path.string(), line_no, word));
      v.push_back(x);
    }
    // Columns x y z block volume (the code reads data[3] as the block and data[4] as
    // the volume, whatever Peridigm's docs say; survey sec. 1.7).
    if (v.size() != 5)
      t.ctx.fail(file_item.mark, fmt::format("{}: {}:{}: expected 5 columns 'x y z block volume', found {}",
                                             file_item.path, path.string(), line_no, v.size()));
    if (v[3] != std::floor(v[3]) || v[3] < 1)
      t.ctx.fail(file_item.mark, fmt::format("{}: {}:{}: the block (4th column) must be a whole number >= 1, found {}",
                                             file_item.path, path.string(), line_no, v[3]));
    if (!(v[4] > 0))
      t.ctx.fail(file_item.mark, fmt::format("{}: {}:{}: the volume (5th column) must be > 0, found {}",
                                             file_item.path, path.string(), line_no, v[4]));
    t.points.push_back({{v[0], v[1], v[2]}, v[4], static_cast<int>(v[3])});
  }
  if (t.points.empty()) t.ctx.fail(file_item.mark, file_item.path + ": the file '" + path.string() + "' holds no points");
}

struct Grid {
  Vec3 origin, length;
  int n[3] = {1, 1, 1};
};

Grid read_grid(Translation& t, const Item& item) {
  MapReader g(t.ctx, item,
              {"Type", "X Origin", "Y Origin", "Z Origin", "X Length", "Y Length", "Z Length", "Number Points X",
               "Number Points Y", "Number Points Z"});
  if (auto type = g.find("Type")) {
    if (squash(read_string(t.ctx, *type)) != "pdquickgrid")
      t.ctx.fail(type->mark, type->path + ": expected PdQuickGrid, found " + text_of(*type));
  }
  Grid grid;
  const char* axes[3] = {"X", "Y", "Z"};
  for (int k = 0; k < 3; ++k) {
    grid.origin[k] = value_number(t.ctx, g.get(std::string(axes[k]) + " Origin", "the grid's lowest corner"));
    grid.length[k] = read_positive(t.ctx, g.get(std::string(axes[k]) + " Length", "the grid's length, > 0"));
    const Item np = g.get(std::string("Number Points ") + axes[k], "points along the axis, >= 1");
    grid.n[k] = read_int(t.ctx, np);
    if (grid.n[k] < 1) t.ctx.fail(np.mark, np.path + ": expected at least 1 point, found " + text_of(np));
  }
  return grid;
}

// PdQuickGrid's tensor-product grid: cell centres, x fastest, each with its cell's
// volume (QuickGrid.cxx; survey sec. 1.7).
void fill_grid(Translation& t, const Grid& g) {
  const Vec3 d{g.length.x / g.n[0], g.length.y / g.n[1], g.length.z / g.n[2]};
  const double volume = d.x * d.y * d.z;
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i)
        t.points.push_back({{g.origin.x + (i + 0.5) * d.x, g.origin.y + (j + 0.5) * d.y, g.origin.z + (k + 0.5) * d.z},
                            volume, 1});
}

// PdQuickGrid's default neighbourhood is a box of n = round(delta/dx) cells per axis
// (0.5 rounds up; QuickGrid.cxx getCellNeighborhoodSize, survey sec. 1.7 and 3.4);
// Horizon's families are spheres |xi| <= delta unless the deck gives family_box. Where
// the box bonds other pairs than the sphere on this grid, the native deck gets
// `family_box: [n_x dx, n_y dy, n_z dz]` (decks whose two agree are left as they were).
void box_neighbourhood(Translation& t, const Grid& g) {
  if (t.several_horizons)
    t.ctx.fail(t.horizon_item->mark, t.horizon_item->path + ": PdQuickGrid's box neighbourhood (no NeighborhoodType) "
                                                            "with blocks of different horizons is not supported; give "
                                                            "NeighborhoodType: Spherical");
  const Vec3 d{g.length.x / g.n[0], g.length.y / g.n[1], g.length.z / g.n[2]};
  int cells[3];
  for (int k = 0; k < 3; ++k) cells[k] = static_cast<int>(std::floor(t.horizon / d[k] + 0.5));
  for (int a = -(g.n[0] - 1); a < g.n[0]; ++a)
    for (int b = -(g.n[1] - 1); b < g.n[1]; ++b)
      for (int c = -(g.n[2] - 1); c < g.n[2]; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const bool box = std::abs(a) <= cells[0] && std::abs(b) <= cells[1] && std::abs(c) <= cells[2];
        const double r = std::sqrt(a * a * d.x * d.x + b * b * d.y * d.y + c * c * d.z * d.z);
        const bool sphere = r <= t.horizon * (1 + 1e-12);
        if (box != sphere) {
          t.out["family_box"] = point_row({cells[0] * d.x, cells[1] * d.y, cells[2] * d.z}, std::nullopt);
          return;
        }
      }
}

// --- Materials and damage ----------------------------------------------------------

YAML::Node read_material(Translation& t, const Item& item) {
  // Keys every Peridigm material shares (Peridigm_Material.cpp), then each model's own.
  std::vector<std::string> keys = {"Material Model",  "Density",          "Bulk Modulus",
                                   "Shear Modulus",   "Young's Modulus",  "Poisson's Ratio",
                                   "Thermal Expansion Coefficient", "Apply Shear Correction Factor",
                                   "Apply Automatic Differentiation Jacobian", "Compute Partial Stress",
                                   "Yield Stress",    "Disable Plasticity", "Hardening Modulus",
                                   "Hourglass Coefficient", "lambda_i", "tau b", "Finite Difference Probe Length",
                                   "Enable Flaw", "Flaw Location X", "Flaw Location Y", "Flaw Location Z",
                                   "Flaw Size", "Flaw Magnitude", "Plane Strain", "Plane Stress", "Height",
                                   "Coefficient", "Use Improved Quadrature", "Dilatation Influence Function",
                                   "Deviatoric Influence Function", "Strain Hardening Exponent",
                                   "Rate Hardening Exponent", "Reference Strain Rate", "Reference Strain 0",
                                   "Reference Strain 1", "Gradient Order Of Accuracy", "Actual Horizon"};
  MapReader m(t.ctx, item, keys);
  const Item model_item = m.get("Material Model", "Elastic, Elastic Bond Based, Elastic Plastic, ...");
  const std::string model = read_string(t.ctx, model_item);
  const std::string w = squash(model);
  if (w == "diffusion") {
    // Peridigm's Diffusion material is Horizon's heat conduction without mechanics (a
    // material of heat alone, docs/input.md): its Flux_Divergence in SimpleImplicitDiffusion's
    // gold is sum_j kappa (T_j - T_i)/|xi| V_j with kappa = 6 k/(pi delta^4), k = Coefficient,
    // at every prescribed point to 1e-15 (docs/peridigm.md): Horizon's inverse kernel with the
    // continuum calibration, conductivity k. Use Improved Quadrature: Horizon's improved
    // quadrature (thermal.quadrature, the optimisation-based weights of Trask, You, Yu and
    // Parks 2019 that the material's option names).
    MapReader d(t.ctx, item, {"Material Model", "Coefficient", "Use Improved Quadrature"});
    YAML::Node mat;
    mat["thermal"]["conductivity"] = number(read_positive(t.ctx, d.get("Coefficient", "the diffusion coefficient k")));
    bool improved = false;
    if (auto q = d.find("Use Improved Quadrature")) improved = read_bool(t.ctx, *q);
    if (t.improved_quadrature && *t.improved_quadrature != improved)
      t.ctx.fail(model_item.mark, model_item.path + ": Diffusion materials that differ in Use Improved Quadrature are "
                                                    "not supported (Horizon's quadrature is the deck's thermal section's)");
    t.improved_quadrature = improved;
    if (!t.diffusion_item) t.diffusion_item = model_item;
    return mat;
  }
  if (!t.mechanical_item) t.mechanical_item = model_item;
  for (const char* k : {"Coefficient", "Use Improved Quadrature"})
    if (auto it = m.find(k))
      t.ctx.fail(*it->key_mark, it->path + ": a parameter of Material Model 'Diffusion' only");
  YAML::Node mat;
  std::vector<std::string> own;  // the model-specific keys this model accepts
  bool planar_c = false;         // Elastic Bond Based in a plane: c given, no moduli
  if (w == "elastic" || w == "elasticpartialvolume") {
    // Elastic Partial Volume is the LPS with Peridigm's partial volumes when its mesh asks
    // for element-horizon intersections (USE_PV builds, survey sec. 1.2); without them (no
    // such key is read here) it is the LPS: LinearLPSBar's gold (docs/peridigm.md).
    mat["model"] = "lps";
  } else if (w == "linearlpspartialvolume") {
    // The linearised LPS (material/models/linear_lps.hpp), without partial volumes as above.
    mat["model"] = "linear_lps";
  } else if (w == "elasticbondbased") {
    mat["model"] = "pmb";
    own = {"Plane Strain", "Plane Stress", "Height"};
    bool planar = false;
    for (const char* k : {"Plane Strain", "Plane Stress"})
      if (auto f = m.find(k); f && read_bool(t.ctx, *f)) {
        if (planar) t.ctx.fail(*f->key_mark, f->path + ": give Plane Strain or Plane Stress, not both");
        planar = true;
      }
    if (planar) {
      // Peridigm's planar bond-based solid (a one-layer mesh of thickness h = Height):
      // c = 12 K/(pi h delta^3). It is Horizon's 2-D micromodulus (material/constants.cpp)
      // in either plane mode when K is the in-plane bulk modulus: plane stress (nu = 1/3)
      // c = 9E/(pi h delta^3), E = 2K(1 - nu) = 4K/3; plane strain (nu = 1/4)
      // c = 48E/(5 pi h delta^3), E = 2K(1 + nu)(1 - 2 nu) = 5K/4. Both golds
      // (ElasticBondBased2DPlaneStrain, ...PlaneStress) have the same forces, and their c
      // fitted from them is 7.2144221e12 = 12 K/(pi h delta^3) to 1e-13 (docs/peridigm.md).
      // The mesh's particles keep their 3-D volumes A h in their plane, so the native deck
      // stays 3-D and takes c directly.
      const double h = read_positive(t.ctx, m.get("Height", "the thickness h of the planar body"));
      const Item k = m.get("Bulk Modulus", "the bulk modulus K (c = 12 K/(pi h delta^3))");
      for (const char* other : {"Shear Modulus", "Young's Modulus", "Poisson's Ratio"})
        if (auto it = m.find(other))
          t.ctx.fail(*it->key_mark, it->path + ": a planar Elastic Bond Based material takes the Bulk Modulus alone");
      const double K = read_positive(t.ctx, k);
      if (!(t.horizon > 0))
        t.ctx.fail(k.mark, k.path + ": a planar Elastic Bond Based material needs one horizon for its blocks (c = 12 K/(pi h "
                                    "delta^3)), not one that varies in space");
      mat["micromodulus"] = number(12 * K / (std::numbers::pi * h * std::pow(t.horizon, 3)));
      planar_c = true;  // the moduli are not given with c (below)
    } else if (auto hk = m.find("Height")) {
      t.ctx.fail(*hk->key_mark, hk->path + ": a parameter of the planar model only (Plane Strain or Plane Stress: true)");
    }
  } else if (w == "elasticplastic" || w == "elasticplastichardening") {
    own = {"Yield Stress", "Disable Plasticity"};
    if (w == "elasticplastichardening") own.push_back("Hardening Modulus");
    bool disabled = false;
    if (auto d = m.find("Disable Plasticity")) disabled = read_bool(t.ctx, *d);
    mat["model"] = "elastic_plastic";
    if (disabled) {
      // Disable Plasticity leaves the model's elastic part, the LPS forces; its Lambda
      // stays 0 (Bar_TwoBlocks_TwoDifferentMaterial_QS's gold has it 0 in that block and
      // undefined in the Elastic one).
      mat["plasticity"] = "off";
      // The yield stress is not used then (BondBreakingInitialVelocity-EP gives 0).
      const double sy = m.find("Yield Stress") ? read_non_negative(t.ctx, *m.find("Yield Stress")) : 0.0;
      mat["yield_stress"] = sy > 0 ? sy : 1.0;
      if (auto h = m.find("Hardening Modulus")) read_non_negative(t.ctx, *h);
    } else {
      mat["yield_stress"] = read_positive(t.ctx, m.get("Yield Stress", "the yield stress [Pa]"));
      if (auto h = m.find("Hardening Modulus")) mat["hardening_modulus"] = read_non_negative(t.ctx, *h);
      // Peridigm's yield function is Mitchell's psi_0 = 25 sigma_y^2/(8 pi delta^5), the
      // continuum sphere's m whatever the lattice (ep_cube's gold, docs/peridigm.md).
      mat["yield_reference"] = "continuum";
    }
  } else if (w == "viscoelastic") {
    own = {"lambda_i", "tau b"};
    mat["model"] = "viscoelastic";
    mat["lambda_1"] = read_number(t.ctx, m.get("lambda_i", "the weight of the Maxwell branch"));
    mat["tau_1"] = read_positive(t.ctx, m.get("tau b", "the Maxwell branch's decay time [s]"));
  } else if (w == "elasticcorrespondence") {
    // Peridigm's correspondence materials integrate the unrotated Cauchy stress in rate
    // form (Flanagan and Taylor 1987): stress_law hypoelastic, which its golds' Cauchy
    // stresses and left stretches fix (material/classical/hypoelastic.hpp), and control
    // zero-energy modes by Littlewood's hourglass force, coefficient Hourglass Coefficient
    // (stabilization_form peridigm; 0 without the key, as Peridigm's default).
    own = {"Hourglass Coefficient"};
    mat["model"] = "correspondence";
    mat["stress_law"] = "hypoelastic";
    mat["rotation_update"] = "peridigm";  // Peridigm's rotation increment (classical/hypoelastic.hpp)
    mat["stabilization_form"] = "peridigm";
    mat["stabilization"] = 0.0;
    if (auto h = m.find("Hourglass Coefficient")) mat["stabilization"] = read_non_negative(t.ctx, *h);
  } else if (w == "elasticbondassociatedcorrespondence" || w == "elastichypoelasticcorrespondence") {
    // Peridigm's bond-associated correspondence (Horizon's bond_associated_correspondence,
    // material/models/bond_associated.hpp): the rate-form law (stress_law hypoelastic) on
    // the bond-level deformation gradient (F_i + F_j)/2 corrected along the bond, energy
    // averaged over the family; ElasticBondAssociatedCorrespondenceFullyPrescribedTension's
    // gold fixes its forces to 1e-15. Elastic Hypoelastic Correspondence under Enable
    // Bond-Associated Hypoelastic Model is the semi-Lagrangian form of the same (the
    // velocity gradients and forces on the current bonds, with Peridigm's volume factor J_n
    // on sigma: ElasticHypoelasticCorrespondenceFullyPrescribedTension's gold, 1e-15).
    const bool hypoelastic = w == "elastichypoelasticcorrespondence";
    own = {"Gradient Order Of Accuracy"};
    mat["model"] = "bond_associated_correspondence";
    mat["stress_law"] = "hypoelastic";
    mat["kinematics"] = hypoelastic ? "semi_lagrangian" : "lagrangian";
    // Peridigm's rotation increment, as for its other correspondence materials (fitted there:
    // classical/hypoelastic.hpp); the bond-associated golds have no rotation to check it.
    mat["rotation_update"] = "peridigm";
    if (hypoelastic && !t.bond_associated_hypoelastic)
      t.ctx.fail(model_item.mark, model_item.path + ": Elastic Hypoelastic Correspondence is mapped in its bond-associated "
                                                    "form only (Enable Bond-Associated Hypoelastic Model: true at the "
                                                    "deck's top level)");
    // Gradient Order Of Accuracy: the order of the polynomial the nonlocal gradient
    // reproduces (Behzadinasab, Trask and Bazilevs 2021's higher-order gradients); Horizon's
    // F_i = (sum omega V Y (x) xi) K^-1 is the first-order one.
    if (auto g = m.find("Gradient Order Of Accuracy"); g && read_number(t.ctx, *g) != 1)
      fail_expected(t.ctx, *g, "1 (the first-order nonlocal gradient; higher orders are not implemented)");
    if (hypoelastic) {
      // Actual Horizon: the radius of the semi-Lagrangian influence function on the
      // current bond length; the neighbour lists come from the block's (larger) Horizon.
      // With Peridigm's default influence function One every bond of the lists acts with
      // omega = 1 whatever its current length: the gold's forces follow the Horizon 0.9
      // families to 1e-15 (with only the bonds within 0.751 they are 25 % off).
      own.push_back("Actual Horizon");
      const Item a = m.get("Actual Horizon", "the horizon of the semi-Lagrangian influence function");
      read_positive(t.ctx, a);
      if (t.influence != "constant")
        t.ctx.fail(a.mark, a.path + ": with an Influence Function other than One the semi-Lagrangian influence on the "
                                    "current bond length is not mapped");
    }
  } else if (w == "elasticplasticcorrespondence" || w == "isotropichardeningcorrespondence" ||
             w == "viscoplasticneedlemancorrespondence") {
    // Correspondence with J2 plasticity (perfect, or with linear isotropic hardening) on
    // the same rate form: stress_law hypoelastic_j2 (docs/peridigm.md); Needleman's
    // viscoplastic flow stress: stress_law viscoplastic_needleman.
    own = {"Hourglass Coefficient", "Yield Stress"};
    mat["model"] = "correspondence";
    const bool needleman = w == "viscoplasticneedlemancorrespondence";
    mat["stress_law"] = needleman ? "viscoplastic_needleman" : "hypoelastic_j2";
    // Peridigm's own return (its hardened yield stress from its plastic-multiplier
    // estimate: classical/hypoelastic.hpp), which the IsotropicHardening golds need.
    if (!needleman) mat["plastic_return"] = "peridigm";
    mat["rotation_update"] = "peridigm";
    mat["stabilization_form"] = "peridigm";
    mat["stabilization"] = 0.0;
    mat["yield_stress"] = read_positive(t.ctx, m.get("Yield Stress", "the yield stress [Pa]"));
    if (auto h = m.find("Hourglass Coefficient")) mat["stabilization"] = read_non_negative(t.ctx, *h);
    if (needleman) {
      const std::tuple<const char*, const char*, const char*, bool> keys[] = {
          {"Strain Hardening Exponent", "strain_hardening_exponent", "the strain hardening exponent N", false},
          {"Rate Hardening Exponent", "rate_hardening_exponent", "the rate hardening exponent m", false},
          {"Reference Strain Rate", "reference_strain_rate", "the reference strain rate [1/s]", true},
          {"Reference Strain 0", "reference_strain", "the reference strain eps_0 of (1 + eps_p/eps_0)^N", true},
          {"Reference Strain 1", "softening_strain", "the softening strain eps_1 of 1 + (eps_p/eps_1)^2", true}};
      for (const auto& [from, to, what, positive] : keys) {
        own.push_back(from);
        const Item it = m.get(from, what);
        mat[to] = positive ? read_positive(t.ctx, it) : read_non_negative(t.ctx, it);
      }
    }
    if (w != "elasticplasticcorrespondence") {
      own.insert(own.end(), {"Enable Flaw", "Flaw Location X", "Flaw Location Y", "Flaw Location Z", "Flaw Size",
                             "Flaw Magnitude"});
      if (!needleman) own.push_back("Hardening Modulus");
      if (auto h = m.find("Hardening Modulus"); h && !needleman)
        mat["hardening_modulus"] = read_non_negative(t.ctx, *h);
      // The flaw: a local knock-down of the yield stress, sigma_y (1 - m exp(-|x -
      // x_f|^2/s^2)) (fitted from IsotropicHardeningPlasticFullyPrescribedTension_WithFlaw's
      // gold; material/models/correspondence.hpp Flaw). Its keys are read either way.
      const bool flaw = m.find("Enable Flaw") && read_bool(t.ctx, *m.find("Enable Flaw"));
      const std::pair<const char*, const char*> keys[] = {{"Flaw Location X", "flaw_x"},
                                                          {"Flaw Location Y", "flaw_y"},
                                                          {"Flaw Location Z", "flaw_z"}};
      for (const auto& [from, to] : keys) {
        if (flaw) mat[to] = read_number(t.ctx, m.get(from, "the flaw's centre coordinate"));
        else if (auto f = m.find(from)) read_number(t.ctx, *f);
      }
      if (flaw) {
        mat["flaw_size"] = read_positive(t.ctx, m.get("Flaw Size", "the flaw's length s (exp(-r^2/s^2))"));
        const Item mag = m.get("Flaw Magnitude", "the flaw's knock-down m of the yield stress, in (0, 1]");
        const double mm = read_number(t.ctx, mag);
        if (!(mm >= 0 && mm <= 1)) fail_expected(t.ctx, mag, "a number in [0, 1]");
        mat["flaw_magnitude"] = mm;
      } else {
        for (const char* k : {"Flaw Size", "Flaw Magnitude"})
          if (auto f = m.find(k)) read_number(t.ctx, *f);
      }
    }
  } else if (w == "pals") {
    // The position-aware linear solid (Mitchell, Silling, Littlewood 2015): Horizon's pals
    // (material/models/pals.hpp), its two influence functions as Peridigm names them.
    // Peridigm's Pals has no hourglass force: the InterfaceAwareDamageModel decks give it
    // an Hourglass Coefficient, which Peridigm ignores; read, no effect.
    own = {"Hourglass Coefficient", "Dilatation Influence Function", "Deviatoric Influence Function"};
    mat["model"] = "pals";
    if (auto h = m.find("Hourglass Coefficient")) read_non_negative(t.ctx, *h);
    const std::pair<const char*, const char*> functions[] = {{"Dilatation Influence Function", "dilatation_influence"},
                                                             {"Deviatoric Influence Function", "deviatoric_influence"}};
    for (const auto& [from, to] : functions) {
      auto f = m.find(from);
      if (!f) continue;  // the native default: the deck's influence function (One unless given)
      const std::string v = squash(read_string(t.ctx, *f));
      if (v == "one" || v == "1" || v == "1.0") mat[to] = "constant";
      else if (v == "1.0/zeta" || v == "1/zeta") mat[to] = "inverse_length";
      else
        t.ctx.fail(f->mark, f->path + ": expected One or \"1.0/zeta\" (the influence functions Horizon maps for "
                                      "Pals), found " + text_of(*f));
    }
  } else {
    // The models of Peridigm's suite Horizon does not map yet (docs/peridigm.md lists the
    // decks each blocks).
    fail_choice(t.ctx, model_item, model,
                {"Elastic", "Elastic Bond Based", "Elastic Plastic", "Elastic Plastic Hardening", "Viscoelastic",
                 "Elastic Correspondence", "Elastic Plastic Correspondence", "Isotropic Hardening Correspondence",
                 "Viscoplastic Needleman Correspondence", "Elastic Bond Associated Correspondence",
                 "Elastic Hypoelastic Correspondence", "Pals", "Elastic Partial Volume", "Linear LPS Partial Volume"},
                "Peridigm material model Horizon reads");
  }
  // A model-specific key given to another model is an error (Peridigm ignores it).
  for (const std::string& k : {std::string("Yield Stress"), std::string("Disable Plasticity"),
                               std::string("Hardening Modulus"), std::string("Hourglass Coefficient"),
                               std::string("lambda_i"), std::string("tau b"), std::string("Enable Flaw"),
                               std::string("Flaw Location X"), std::string("Flaw Location Y"),
                               std::string("Flaw Location Z"), std::string("Flaw Size"),
                               std::string("Flaw Magnitude"), std::string("Plane Strain"), std::string("Plane Stress"),
                               std::string("Height"), std::string("Dilatation Influence Function"),
                               std::string("Deviatoric Influence Function"), std::string("Strain Hardening Exponent"),
                               std::string("Rate Hardening Exponent"), std::string("Reference Strain Rate"),
                               std::string("Reference Strain 0"), std::string("Reference Strain 1"),
                               std::string("Gradient Order Of Accuracy"), std::string("Actual Horizon")}) {
    if (std::find(own.begin(), own.end(), k) != own.end()) continue;
    if (auto it = m.find(k))
      t.ctx.fail(*it->key_mark, it->path + ": not a parameter of Material Model '" + model + "'");
  }
  mat["density"] = read_positive(t.ctx, m.get("Density", "the mass density"));
  const std::pair<const char*, const char*> moduli[] = {{"Bulk Modulus", "bulk_modulus"},
                                                        {"Shear Modulus", "shear_modulus"},
                                                        {"Young's Modulus", "youngs_modulus"},
                                                        {"Poisson's Ratio", "poissons_ratio"}};
  if (!planar_c) {
    for (const auto& [from, to] : moduli)
      if (auto v = m.find(from)) mat[to] = read_number(t.ctx, *v);
  }
  if (auto a = m.find("Thermal Expansion Coefficient")) {
    // The thermal strain alpha (T - T(0)) of Horizon's thermal expansion (docs/models/heat.md;
    // Kilic and Madenci 2010, Oterkus, Madenci and Agwai 2014: the bond's mechanical stretch
    // s - alpha dT), its reference each particle's temperature at t = 0 (ThermalExpansionCube's
    // gold: Temperature_Change = T - 273 and displacements alpha dT x from it).
    if (const double alpha = read_number(t.ctx, *a); alpha != 0) {
      mat["thermal"]["expansion"] = number(alpha);
      mat["thermal"]["reference_temperature"] = "initial";
      // Elastic Correspondence keeps its rate form, which takes the thermal strain's
      // increment out of its volumetric strain increment as Peridigm does
      // (ThermalExpansionCubeElasticCorrespondence's gold: V = (1 + alpha dT)^n). Peridigm's
      // plastic correspondence models refuse a Thermal Expansion Coefficient; Horizon gives
      // such a material the total form j2, whose split of F into elastic and
      // thermal parts expands a free body stress-free (docs/peridigm.md).
      if (mat["stress_law"]) {
        const std::string law = mat["stress_law"].as<std::string>();
        if (law == "viscoplastic_needleman")
          t.ctx.fail(a->mark, a->path + ": Viscoplastic Needleman Correspondence with thermal expansion is not supported");
        if (law == "hypoelastic_j2") {
          if (mat["flaw_magnitude"])
            t.ctx.fail(a->mark, a->path + ": a flawed material (Enable Flaw) with thermal expansion is not supported");
          mat["stress_law"] = "j2";
        }
      }
    }
  }
  if (auto f = m.find("Compute Partial Stress"); f && read_bool(t.ctx, *f))
    t.ctx.fail(f->mark, f->path + ": not supported; only false");
  if (auto f = m.find("Apply Shear Correction Factor"); f && read_bool(t.ctx, *f)) {
    // Peridigm's per-particle factor on the deviatoric modulus of its Elastic and Elastic
    // Plastic solids: Horizon's shear_correction (material/shear_correction.hpp), derived
    // from the LPS's deviatoric energy under shear (Peridigm's own definition is in its
    // code alone: docs/peridigm.md).
    const std::string native = mat["model"] ? mat["model"].as<std::string>() : std::string();
    if (native != "lps" && native != "elastic_plastic")
      t.ctx.fail(f->mark, f->path + ": a shear correction of the Elastic and Elastic Plastic materials only (the LPS "
                                    "deviatoric modulus), not of Material Model '" + model + "'");
    mat["shear_correction"] = true;
  }
  // Apply Automatic Differentiation Jacobian and Finite Difference Probe Length choose
  // how Peridigm builds its tangent; Horizon's Newton solver has its own. Read, no effect.
  if (auto f = m.find("Apply Automatic Differentiation Jacobian")) read_bool(t.ctx, *f);
  if (auto f = m.find("Finite Difference Probe Length")) read_positive(t.ctx, *f);
  return mat;
}

std::string read_value(Translation& t, const Item& item);

// Whether an expression's text names the time t (a word t, as the static solver reads it:
// solver/static_driver.cpp uses_time).
bool mentions_t(const std::string& s) {
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i] == 't' && (i == 0 || !word(s[i - 1])) && (i + 1 == s.size() || !word(s[i + 1]))) return true;
  return false;
}

// Appends precracks to the native deck's list.
void add_precracks(Translation& t, const YAML::Node& cracks) {
  for (const auto& c : cracks) t.out["precracks"].push_back(c);
}

// A damage model's native `damage` node; null for Initial Damage, whose bond filters
// become precracks with broken bonds (and no bond breaks later).
YAML::Node read_damage(Translation& t, const Item& item) {
  MapReader m(t.ctx, item, {"Damage Model", "Critical Stretch", "Thermal Expansion Coefficient", "Bond Filters",
                            "Time Dependent Critical Stretch"});
  const Item model_item = m.get("Damage Model", "Critical Stretch");
  const std::string model = read_string(t.ctx, model_item);
  if (squash(model) == "initialdamage") {
    // Peridigm's Initial Damage breaks the bonds that cross its filters at the start
    // (survey sec. 1.3); they stay in the families (Number_Of_Neighbors, Damage).
    for (const char* k : {"Critical Stretch", "Thermal Expansion Coefficient"})
      if (auto it = m.find(k)) t.ctx.fail(*it->key_mark, it->path + ": not a parameter of Damage Model '" + model + "'");
    add_precracks(t, read_bond_filters(t.ctx, m.get("Bond Filters", "the filters whose crossing bonds start broken"),
                                       true));
    return YAML::Node();
  }
  if (auto it = m.find("Bond Filters"))
    t.ctx.fail(*it->key_mark, it->path + ": a parameter of Damage Model 'Initial Damage' only");
  // Horizon breaks a bond at the smaller critical stretch of its two ends (solver/forces.cpp):
  // Peridigm's Interface Aware rule. Peridigm's plain Critical Stretch judges each directed
  // bond by its own end's block; the two agree within a block (docs/peridigm.md).
  const std::string w = squash(model);
  if (w != "criticalstretch" && w != "interfaceaware" && w != "timedependentcriticalstretch")
    fail_choice(t.ctx, model_item, model,
                {"Critical Stretch", "Interface Aware", "Time Dependent Critical Stretch", "Initial Damage"},
                "Peridigm damage model Horizon reads");
  // A Thermal Expansion Coefficient here is checked against the block's material's
  // (same_damage_expansion, below).
  if (auto a = m.find("Thermal Expansion Coefficient")) read_number(t.ctx, *a);
  YAML::Node d;
  const bool in_time = w == "timedependentcriticalstretch";
  const char* own = in_time ? "Time Dependent Critical Stretch" : "Critical Stretch";
  for (const char* k : {"Critical Stretch", "Time Dependent Critical Stretch"})
    if (auto it = m.find(k); it && std::string(k) != own)
      t.ctx.fail(*it->key_mark, it->path + ": not a parameter of Damage Model '" + model + "'");
  if (in_time) {
    // s_c(t) as a function string (survey sec. 1.3): the native critical stretch as an
    // expression in t, evaluated at each explicit step.
    d["critical_stretch"] = read_value(t, m.get(own, "the critical stretch as a function of t"));
  } else {
    d["critical_stretch"] = read_positive(t.ctx, m.get(own, "the critical bond stretch, > 0"));
  }
  return d;
}

// Peridigm's damage models judge the stretch less their own alpha dT; Horizon's breaking
// test takes the mechanical stretch of the material's thermal strain (docs/models/heat.md),
// so the two coefficients must agree.
void same_damage_expansion(Translation& t, const Item& damage, const YAML::Node& mat) {
  if (!damage.node.IsMap()) return;
  const double material = mat["thermal"] ? mat["thermal"]["expansion"].as<double>() : 0.0;
  for (const auto& e : map_entries(t.ctx, damage))
    if (e.key == "Thermal Expansion Coefficient" && read_number(t.ctx, e.value) != material)
      t.ctx.fail(e.value.mark, fmt::format("{}: {} differs from the block's material's Thermal Expansion Coefficient "
                                           "({}); Horizon's bonds break on the stretch less the material's own "
                                           "thermal strain",
                                           e.value.path, read_number(t.ctx, e.value), material));
}

// --- Boundary conditions -----------------------------------------------------------

std::vector<int> read_ids(Translation& t, const Item& item) {
  const std::string text = read_string(t.ctx, item);
  std::vector<int> ids;
  std::istringstream in(text);
  std::string word;
  bool numeric = true;
  while (in >> word) {
    char* end = nullptr;
    const long v = std::strtol(word.c_str(), &end, 10);
    if (*end != '\0' || end == word.c_str()) {
      numeric = false;
      break;
    }
    ids.push_back(static_cast<int>(v));
  }
  if (!numeric) {
    // A file of ids, one a line (Peridigm_BoundaryAndInitialConditionManager.cpp).
    ids.clear();
    const fs::path path = resolve_deck_file(t.folder.string(), text);
    std::ifstream f(path);
    if (!f)
      t.ctx.fail(item.mark, item.path + ": expected node ids (\"1 2 3\") or a file of them; cannot open '" +
                                path.string() + "'");
    // Rows starting with #, / or * are comments, as in a text-file discretisation
    // (PredictorFromPreviousSolver's node-set files open with "# Volume = ...").
    for (std::string line; std::getline(f, line);) {
      const auto first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#' || line[first] == '/' || line[first] == '*') continue;
      std::istringstream row(line);
      while (row >> word) {
        char* end = nullptr;
        const long v = std::strtol(word.c_str(), &end, 10);
        if (*end != '\0' || end == word.c_str())
          t.ctx.fail(item.mark, item.path + ": the node-set file '" + path.string() + "' holds '" + word +
                                    "', not a node id");
        ids.push_back(static_cast<int>(v));
      }
    }
  }
  if (ids.empty()) t.ctx.fail(item.mark, item.path + ": the node set is empty");
  return ids;
}

// The deck's node-set lists hold 1-based ids (Peridigm's survey sec. 1.6), except in a deck
// where some list holds the id 0: Peridigm's ElementVariableOutput names its two points
// "0" and "1", and its gold moves both (the points of Compression_2x1x1, "1" and "2", the
// same way), so such a deck counts from 0 in every list. Checks each id's range.
void number_from_one(Translation& t, std::map<std::string, std::vector<int>>& sets,
                     const std::map<std::string, Item>& items) {
  bool zero_based = false;
  for (const auto& [name, item] : items)
    for (int id : sets[name]) zero_based = zero_based || id == 0;
  for (const auto& [name, item] : items)
    for (int& id : sets[name]) {
      if (zero_based) ++id;
      if (id < 1 || static_cast<std::size_t>(id) > t.points.size())
        t.ctx.fail(item.mark,
                   fmt::format("{}: node id {} is out of range: the discretisation has nodes {} to {}{}", item.path,
                               zero_based ? id - 1 : id, zero_based ? 0 : 1, zero_based ? t.points.size() - 1 : t.points.size(),
                               zero_based ? " (the deck's node sets count from 0: one of them holds the id 0)" : ""));
    }
}

// An expression in x, y, z, t as Horizon's muParser reads it: kept as written when
// muParser reads it, else translated from Peridigm's C-style function string
// (function_string.hpp), whose mistakes are reported at their line and column.
std::string read_value(Translation& t, const Item& item) {
  if (!item.node.IsScalar()) fail_expected(t.ctx, item, "a number or an expression in x, y, z and t");
  const std::string text = item.node.Scalar();
  try {
    Expression e(text);
    return text;
  } catch (const Error&) {
  }
  std::string translated;
  try {
    translated = function_string_to_muparser(text);
  } catch (const FunctionStringError& err) {
    // A quoted scalar's text starts one column after its mark (the quote).
    YAML::Mark at = item.mark;
    at.column += static_cast<int>(err.offset) + (item.node.Tag() == "!" ? 1 : 0);
    t.ctx.fail(at, item.path + ": cannot read the function string: " + err.what());
  }
  try {
    Expression e(translated);
  } catch (const Error& err) {
    t.ctx.fail(item.mark, item.path + ": the function string '" + text + "' became '" + translated +
                              "', which does not read (" + err.what() + ")");
  }
  return translated;
}

// --- Solvers ---------------------------------------------------------------------------

// Horizon's native solver for a deck's solvers (one, or several in sequence merged).
struct Solve {
  YAML::Node solver;       // native `solver` (of a staged deck: its explicit stage)
  std::string method;      // Verlet, QuasiStatic, NOXQuasiStatic, Implicit
  double start_time = 0;   // a staged deck's explicit stage: the static stage's end
  double end_time = 1;
  std::optional<double> fixed_dt;
  int load_steps = 1;      // static
  // static: the load steps' times when they are not equal (QuasiStatic `Time Steps`;
  // native solver.load_times), from the solver's Initial Time to its Final Time.
  std::vector<double> load_times;
  // static: the Initial Times of the solvers merged into this one after the first (native
  // solver_starts: Peridigm writes each solver's start state again).
  std::vector<double> solver_starts;
  // A QuasiStatic solver followed by Verlet: the static stage (native `solver: [static,
  // explicit]`, docs/input.md "Solver stages"); this Solve is then the Verlet stage.
  std::shared_ptr<Solve> static_stage;
  // A QuasiStatic solver's Adaptive Load-Stepping.Switch to Verlet: the explicit stage it
  // falls back to (native `explicit` solver map), and its Output Frequency (0: none).
  YAML::Node switch_to_verlet;
  int switch_output_every = 0;
};

// A NOX sublist Horizon reads without effect: NOX's own settings of the path its
// nonlinear iteration takes (line search, linear solve, preconditioner reuse, printing),
// which do not change the equilibrium it converges to. It must be a map.
void read_nox_sublist(const DeckContext& ctx, const Item& item) {
  if (!item.node.IsMap()) fail_expected(ctx, item, "a map (a NOX parameter list)");
}

// QuasiStatic's `Adaptive Load-Stepping` (Peridigm cuts a load step whose Newton solve
// fails, up to the reductions it allows, then optionally finishes with Verlet): Horizon's
// static driver cuts a failing load step itself (solver/static_driver.hpp), so the
// reductions are read, their values checked, without effect (with a Switch to Verlet the
// reductions in one step are max_step_cuts). `Switch to Verlet` {Safety
// Factor or Fixed dt, Output Frequency}, Peridigm's explicit fallback once its reductions
// are spent, becomes a staged run whose static stage has on_failure: explicit (read_solvers).
void read_adaptive_load_stepping(const DeckContext& ctx, const Item& item, Solve& r) {
  MapReader a(ctx, item,
              {"Maximum load step reductions in one step", "Maximum total load step reductions",
               "Reduce all remaining load steps", "Adaptive output frequency", "Switch to Verlet"});
  for (const char* k : {"Maximum load step reductions in one step", "Maximum total load step reductions"})
    if (auto n = a.find(k); n && read_int(ctx, *n) < 0) fail_expected(ctx, *n, "a whole number >= 0");
  for (const char* k : {"Reduce all remaining load steps", "Adaptive output frequency"})
    if (auto b = a.find(k)) read_bool(ctx, *b);
  if (auto v = a.find("Switch to Verlet")) {
    MapReader sv(ctx, *v, {"Safety Factor", "Fixed dt", "Output Frequency"});
    YAML::Node e;
    e["type"] = "explicit";
    if (sv.has("Fixed dt") && sv.has("Safety Factor"))
      ctx.fail(*sv.find("Safety Factor")->key_mark, v->path + ": give Fixed dt or Safety Factor, not both");
    if (auto f = sv.find("Fixed dt")) e["time_step"] = number(read_positive(ctx, *f));
    if (auto f = sv.find("Safety Factor")) {
      const double sf = read_positive(ctx, *f);
      if (sf > 1) fail_expected(ctx, *f, "a safety factor in (0, 1]");
      e["safety_factor"] = number(sf);
    }
    if (auto f = sv.find("Output Frequency")) {
      r.switch_output_every = read_int(ctx, *f);
      if (r.switch_output_every < 1) fail_expected(ctx, *f, "a whole number >= 1");
    }
    r.switch_to_verlet = e;
    // With the switch the reductions decide when the run turns explicit: Peridigm's
    // reductions in one step are Horizon's halvings of one increment (max_step_cuts).
    if (auto n = a.find("Maximum load step reductions in one step")) r.solver["max_step_cuts"] = read_int(ctx, *n);
  }
}

// QuasiStatic's `Time Steps`: the load steps' times, a string of numbers ("0.0 .25 .5
// 1.0", Pals_Simple_Shear), one load step from each to the next (the gold's frames are at
// exactly those times). They run from the solver's Initial Time t0, increasing, to its
// Final Time when the list gives one (without one the last time is the Final Time).
std::vector<double> read_time_steps(const DeckContext& ctx, const Item& item, double t0, std::optional<double> end) {
  const std::string text = read_string(ctx, item);
  std::vector<double> times;
  std::istringstream in(text);
  std::string word;
  while (in >> word) {
    const char* begin = word.c_str();
    char* stop = nullptr;
    errno = 0;
    const double t = std::strtod(begin, &stop);
    if (stop == begin || *stop != '\0' || errno == ERANGE || !std::isfinite(t))
      ctx.fail(item.mark, fmt::format("{}: '{}' is not a number (expected times separated by spaces, e.g. \"0.0 0.1 "
                                      "0.5 1.0\")", item.path, word));
    if (!times.empty() && !(t > times.back()))
      ctx.fail(item.mark, fmt::format("{}: {} does not come after {} (expected increasing times)", item.path, word,
                                      times.back()));
    times.push_back(t);
  }
  if (times.size() < 2)
    fail_expected(ctx, item, "at least two times separated by spaces (the start and the end of a load step)");
  if (times.front() != t0)
    ctx.fail(item.mark, fmt::format("{}: the first time {} is not the solver's Initial Time {}", item.path,
                                    times.front(), t0));
  if (end && times.back() != *end)
    ctx.fail(item.mark, fmt::format("{}: the last time {} is not the solver's Final Time {}", item.path, times.back(),
                                    *end));
  return times;
}

// A static solver's pseudo-times in its native map: end_time (equal load steps), or
// load_times when the steps are listed (native decks give one or the other).
void set_static_times(Solve& r) {
  if (r.load_times.empty()) {
    r.solver["end_time"] = number(r.end_time);
    return;
  }
  r.solver.remove("end_time");
  r.solver.remove("load_steps");
  YAML::Node times(YAML::NodeType::Sequence);
  times.SetStyle(YAML::EmitterStyle::Flow);
  for (double t : r.load_times) times.push_back(number(t));
  r.solver["load_times"] = times;
}

// One solver list (Solver, Solver1, ...); `t0` gets its Initial Time.
Solve read_solver_list(const DeckContext& ctx, const Item& item, double& t0) {
  MapReader s(ctx, item,
              {"Verbose", "Initial Time", "Final Time", "Verlet", "QuasiStatic", "NOXQuasiStatic", "Implicit",
               "ImplicitDiffusion", "Peridigm Preconditioner", "Initialize Predictor From Previous Solver",
               "Solve For Displacement", "Solve For Temperature", "Solve For Pressure"});
  if (auto v = s.find("Verbose")) read_bool(ctx, *v);
  t0 = 0;
  if (auto i = s.find("Initial Time")) {
    t0 = read_number(ctx, *i);
    if (t0 < 0) fail_expected(ctx, *i, "a time >= 0");
  }
  Solve r;
  // Peridigm's default Final Time is 1 (survey sec. 1.5).
  r.end_time = s.has("Final Time") ? read_positive(ctx, *s.find("Final Time")) : 1.0;
  if (auto f = s.find("Final Time"); f && !(r.end_time > t0))
    ctx.fail(f->mark, fmt::format("{}: expected a time after the Initial Time {}", f->path, t0));
  // Peridigm Preconditioner (None, Full Tangent, Block 3x3) chooses how NOX's matrix-free
  // Newton preconditions its linear solves; Horizon assembles its own tangent. Read, no effect.
  if (auto p = s.find("Peridigm Preconditioner")) {
    const std::string w = squash(read_string(ctx, *p));
    if (w != "none" && w != "fulltangent" && w != "block3x3")
      fail_choice(ctx, *p, read_string(ctx, *p), {"None", "Full Tangent", "Block 3x3"}, "Peridigm Preconditioner");
  }
  // Whether Peridigm's Newton starts from the previous solver's last increment: the
  // equilibrium it converges to is the same. Read, no effect.
  if (auto p = s.find("Initialize Predictor From Previous Solver")) read_bool(ctx, *p);
  r.method = *s.exactly_one({"Verlet", "QuasiStatic", "NOXQuasiStatic", "Implicit", "ImplicitDiffusion"}, true);
  const Item mi = *s.find(r.method);
  YAML::Node& solver = r.solver;
  // What the solver solves for (Peridigm's multiphysics switches; default: displacement
  // alone). The ImplicitDiffusion solver solves for the temperature alone; the others for
  // the displacement alone (temperature and pressure with it: Peridigm's Multiphysics, not
  // mapped).
  const bool diffusion = r.method == "ImplicitDiffusion";
  for (const char* k : {"Solve For Displacement", "Solve For Temperature", "Solve For Pressure"}) {
    const auto f = s.find(k);
    if (!f) continue;
    const bool on = read_bool(ctx, *f);
    const std::string key = k;
    const bool wanted = key == "Solve For Displacement" ? !diffusion : key == "Solve For Temperature" ? diffusion : false;
    if (on != wanted)
      ctx.fail(f->mark, f->path + ": " + (on ? "true" : "false") + " is not supported with the " + r.method +
                            " solver (" + (diffusion ? "it solves for the temperature alone" :
                                                       "it solves for the displacement alone; a coupled solve, "
                                                       "Peridigm's Multiphysics, is not mapped") + ")");
  }
  if (diffusion) {
    // Peridigm's ImplicitDiffusion: a steady solve of the diffusion at each of its load
    // steps' times (its gold's free points have no flux divergence): Horizon's heat run with
    // thermal.integration: steady, one step per load step (docs/peridigm.md).
    MapReader v(ctx, mi, {"Number of Load Steps", "Relative Tolerance", "Absolute Tolerance", "Maximum Solver Iterations"});
    solver["type"] = "heat";
    if (auto n = v.find("Number of Load Steps")) {
      r.load_steps = read_int(ctx, *n);
      if (r.load_steps < 1) fail_expected(ctx, *n, "a whole number >= 1");
    }
    // Horizon's heat solve runs to round-off; the tolerances and iterations are read only.
    for (const char* k : {"Relative Tolerance", "Absolute Tolerance"})
      if (auto f = v.find(k)) read_positive(ctx, *f);
    if (auto i = v.find("Maximum Solver Iterations"); i && read_int(ctx, *i) < 1)
      fail_expected(ctx, *i, "a whole number >= 1");
    r.fixed_dt = (r.end_time - t0) / r.load_steps;
    solver["time_step"] = number(*r.fixed_dt);
    return r;
  }
  if (r.method == "Verlet") {
    MapReader v(ctx, mi, {"Fixed dt", "Safety Factor"});
    solver["type"] = "explicit";
    // The step rounded as Peridigm's Verlet rounds it (docs/peridigm.md "Round-off"): the
    // two-point decks' golds hold ForceX to 1e-9 on 4.6e7, below one ulp.
    solver["verlet"] = "peridigm";
    if (v.has("Fixed dt") && v.has("Safety Factor"))
      ctx.fail(*v.find("Safety Factor")->key_mark, mi.path + ": give Fixed dt or Safety Factor, not both");
    if (auto f = v.find("Fixed dt")) r.fixed_dt = read_positive(ctx, *f), solver["time_step"] = number(*r.fixed_dt);
    if (auto f = v.find("Safety Factor")) solver["safety_factor"] = read_positive(ctx, *f);
  } else if (r.method == "Implicit") {
    MapReader v(ctx, mi, {"Fixed dt", "Beta", "Gamma", "Absolute Tolerance", "Maximum Solver Iterations"});
    solver["type"] = "implicit_dynamic";
    // Peridigm's Newmark starts from a_0 = 0: Body_Force_Implicit's free body under b falls
    // u_n = dt^2 (b/rho) (1/4 + n(n - 1)/2) (its gold's 0.0030025 at n = 25), not (b/rho) t^2/2.
    solver["initial_acceleration"] = "zero";
    r.fixed_dt = read_positive(ctx, v.get("Fixed dt", "the time step"));
    solver["time_step"] = number(*r.fixed_dt);
    if (auto b = v.find("Beta"); b && read_number(ctx, *b) != 0.25)
      ctx.fail(b->mark, b->path + ": only 0.25 (Horizon's Newmark is the average-acceleration rule)");
    if (auto g = v.find("Gamma"); g && read_number(ctx, *g) != 0.5)
      ctx.fail(g->mark, g->path + ": only 0.5 (Horizon's Newmark is the average-acceleration rule)");
    if (auto a = v.find("Absolute Tolerance")) read_positive(ctx, *a);
    if (auto i = v.find("Maximum Solver Iterations")) solver["max_iterations"] = read_int(ctx, *i);
  } else {
    // QuasiStatic (Peridigm's Newton) and NOXQuasiStatic (Newton, or nonlinear CG, through
    // NOX) both map to Horizon's static Newton solve: each finds the equilibrium at each
    // load step, and their converged answers agree to the tolerance (docs/peridigm.md).
    const bool nox = r.method == "NOXQuasiStatic";
    MapReader v(ctx, mi,
                nox ? std::vector<std::string>{"Number of Load Steps", "Time Steps", "Absolute Tolerance",
                                               "Relative Tolerance", "Max Solver Iterations", "Nonlinear Solver",
                                               "Direction", "Line Search", "Max Age Of Prec", "Printing",
                                               "Solver Options", "Trust Region"}
                    : std::vector<std::string>{"Number of Load Steps", "Time Steps", "Absolute Tolerance",
                                               "Relative Tolerance", "Maximum Solver Iterations",
                                               "Belos Linear Solver", "Adaptive Load-Stepping"});
    solver["type"] = "static";
    solver["method"] = "newton";
    // Peridigm's quasi-static current positions, (X + u_n) + Delta u over a load step
    // (Pals_Simple_Shear's gold: its forces to the bit; docs/peridigm.md, Round-off).
    solver["positions"] = "peridigm";
    // Peridigm's Newton, run to its absolute tolerance, ends far below it (its golds'
    // displacements agree with Horizon's to 1e-15 when Horizon converges to 1e-12; at
    // Horizon's default 1e-6 they differ by 1e-9 relative, and Peridigm's quasi-static
    // velocity, the last step's displacement increment over its time increment, by more
    // than the golds' tolerances). Newton stops anyway where no step lowers the residual.
    // A Relative Tolerance below 1e-12 tightens it.
    double tolerance = 1.0e-12;
    if (auto a = v.find("Absolute Tolerance")) read_positive(ctx, *a);
    if (auto rt = v.find("Relative Tolerance")) {
      const double rel = read_positive(ctx, *rt);
      if (rel >= 1) fail_expected(ctx, *rt, "a relative tolerance < 1");
      tolerance = std::min(tolerance, rel);
    }
    solver["tolerance"] = tolerance == 1.0e-12 ? YAML::Node("1.0e-12") : number(tolerance);
    if (auto n = v.find("Number of Load Steps")) {
      r.load_steps = read_int(ctx, *n);
      if (r.load_steps < 1) fail_expected(ctx, *n, "a whole number >= 1");
      solver["load_steps"] = r.load_steps;
    }
    if (auto ts = v.find("Time Steps")) {
      if (v.has("Number of Load Steps"))
        ctx.fail(*ts->key_mark, ts->path + ": give Time Steps or Number of Load Steps, not both");
      r.load_times = read_time_steps(ctx, *ts, t0, s.has("Final Time") ? std::optional<double>(r.end_time) : std::nullopt);
      r.load_steps = static_cast<int>(r.load_times.size()) - 1;
      r.end_time = r.load_times.back();
    }
    // Horizon's Newton runs to 1e-12 (above) where Peridigm's stops at its absolute
    // tolerance, and with a finite-difference tangent it converges linearly (about two
    // decades an iteration on ThermalExpansionCubeElasticCorrespondence, 9 to 12 iterations a
    // load step against the deck's 10): Peridigm's limit, below Horizon's default 30, would
    // cut load steps Peridigm takes whole, which changes a rate-form result. So the limit
    // is at least 30, except under Adaptive Load-Stepping, whose reductions and Switch to
    // Verlet the deck ties to its own limit.
    const bool adaptive = static_cast<bool>(v.find("Adaptive Load-Stepping"));
    for (const char* k : {"Maximum Solver Iterations", "Max Solver Iterations"})
      if (auto i = v.find(k)) solver["max_iterations"] = adaptive ? read_int(ctx, *i) : std::max(read_int(ctx, *i), 30);
    // The Krylov method of Peridigm's linear solves; Horizon's are its own. Read, no effect.
    if (auto b = v.find("Belos Linear Solver")) read_string(ctx, *b);
    if (auto a = v.find("Adaptive Load-Stepping")) read_adaptive_load_stepping(ctx, *a, r);
    if (auto n = v.find("Nonlinear Solver")) {
      // NOX's Newton-type solvers: a line search or a trust region globalises the same
      // Newton step; Horizon's Newton has its own safeguard (step cuts).
      const std::string w = squash(read_string(ctx, *n));
      if (w != "linesearchbased" && w != "inexacttrustregionbased" && w != "trustregionbased")
        fail_choice(ctx, *n, read_string(ctx, *n), {"Line Search Based", "Trust Region Based", "Inexact Trust Region Based"},
                    "NOX nonlinear solver Horizon maps to its Newton solve");
    }
    if (auto a = v.find("Max Age Of Prec")) read_int(ctx, *a);
    for (const char* k : {"Line Search", "Printing", "Solver Options", "Trust Region"})
      if (auto l = v.find(k)) read_nox_sublist(ctx, *l);
    if (auto dir = v.find("Direction")) {
      MapReader dm(ctx, *dir, {"Method", "Newton", "Nonlinear CG", "Steepest Descent"});
      if (auto meth = dm.find("Method")) {
        // Nonlinear CG minimises the same energy whose stationary point Newton finds.
        const std::string w = squash(read_string(ctx, *meth));
        if (w != "newton" && w != "nonlinearcg")
          fail_choice(ctx, *meth, read_string(ctx, *meth), {"Newton", "NonlinearCG"},
                      "NOX direction Horizon maps to its Newton solve");
      }
      for (const char* k : {"Newton", "Nonlinear CG", "Steepest Descent"})
        if (auto l = dm.find(k)) read_nox_sublist(ctx, *l);
    }
  }
  return r;
}

// The deck's solver lists in the order given. Several become one native solver when they
// are one run cut in pieces: the same method and options, each starting where the one
// before ended (the first at 0), and the same time step (static: the same time per load
// step, so their load steps are Horizon's equal increments). Anything else is an error.
Solve read_solvers(const DeckContext& ctx, const std::vector<std::string>& keys, const MapReader& m) {
  Solve merged;
  double end = 0;
  std::string first_key;
  std::shared_ptr<Solve> static_stage;  // the QuasiStatic solvers before a Verlet one
  for (const auto& key : keys) {
    const Item item = *m.find(key);
    double t0 = 0;
    Solve sv = read_solver_list(ctx, item, t0);
    const MapReader s(ctx, item, {"Verbose", "Initial Time", "Final Time", "Verlet", "QuasiStatic", "NOXQuasiStatic",
                                   "Implicit", "ImplicitDiffusion", "Peridigm Preconditioner",
                                   "Initialize Predictor From Previous Solver", "Solve For Displacement",
                                   "Solve For Temperature", "Solve For Pressure"});
    const Item at = s.find("Initial Time") ? *s.find("Initial Time") : item;
    if (first_key.empty()) {
      if (t0 != 0) ctx.fail(at.mark, at.path + ": only 0 is supported (Horizon's runs start at t = 0)");
      merged = sv;
      first_key = key;
      end = sv.end_time;
      continue;
    }
    auto refuse = [&](const std::string& why) {
      ctx.fail(item.mark, fmt::format("{}: Horizon runs one solver a deck; {} cannot continue {} as one run: {}", key,
                                      key, first_key, why));
    };
    if (merged.switch_to_verlet.IsMap() || sv.switch_to_verlet.IsMap())
      refuse("a QuasiStatic solver with Switch to Verlet is staged alone (its explicit fallback ends the run)");
    if (std::abs(t0 - end) > 1e-12 * std::max(1.0, std::abs(end)))
      refuse(fmt::format("its Initial Time {} is not where the solver before it ended ({})", t0, end));
    // A Verlet solver after QuasiStatic ones: Horizon's staged run (the static solve, then
    // the explicit run from its state with the last load step's velocity; docs/peridigm.md).
    if (sv.method == "Verlet" && merged.solver["type"].as<std::string>() == "static" && !static_stage) {
      // (YAML::Node assignment writes through to the node it shares: a clone, and reset.)
      static_stage = std::make_shared<Solve>();
      static_stage->solver = YAML::Clone(merged.solver);
      static_stage->method = merged.method;
      static_stage->end_time = merged.end_time;
      static_stage->load_steps = merged.load_steps;
      static_stage->load_times = merged.load_times;
      set_static_times(*static_stage);
      merged.solver.reset(sv.solver);
      merged.method = sv.method;
      merged.fixed_dt = sv.fixed_dt;
      merged.end_time = sv.end_time;
      merged.load_steps = sv.load_steps;
      merged.load_times.clear();
      merged.start_time = t0;
      first_key = key;
      end = sv.end_time;
      continue;
    }
    if (static_stage && sv.method != "Verlet")
      refuse(fmt::format("a {} solver after the Verlet one that follows a QuasiStatic one (Horizon stages a "
                         "static solve and one explicit run)", sv.method));
    if (sv.method != merged.method && !(sv.solver["type"].as<std::string>() == "static" &&
                                        merged.solver["type"].as<std::string>() == "static"))
      refuse(fmt::format("a {} solver after a {} one", sv.method, merged.method));
    auto emit = [](YAML::Node n) {
      n.remove("load_steps");
      n.remove("load_times");
      YAML::Emitter e;
      e << n;
      return std::string(e.c_str());
    };
    if (emit(YAML::Clone(sv.solver)) != emit(YAML::Clone(merged.solver)))
      refuse("its options differ (time step, iterations or tolerances)");
    if (sv.solver["type"].as<std::string>() == "static") {
      const double h0 = merged.end_time / merged.load_steps, h = (sv.end_time - t0) / sv.load_steps;
      if (merged.load_times.empty() && sv.load_times.empty() && std::abs(h - h0) <= 1e-12 * h0) {
        merged.load_steps += sv.load_steps;
        merged.solver["load_steps"] = merged.load_steps;
      } else {
        // Steps of other lengths: one path through the listed times (solver.load_times),
        // each solver's steps at the times it gives them (equal ones: t0 + k (T - t0) / n).
        auto times = [](const Solve& r, double start) {
          if (!r.load_times.empty()) return r.load_times;
          std::vector<double> t;
          for (int k = 0; k <= r.load_steps; ++k)
            t.push_back(k == r.load_steps ? r.end_time : start + k * ((r.end_time - start) / r.load_steps));
          return t;
        };
        std::vector<double> all = times(merged, 0), more = times(sv, t0);
        all.insert(all.end(), more.begin() + 1, more.end());
        merged.load_times = all;
        merged.load_steps = static_cast<int>(all.size()) - 1;
      }
      merged.solver_starts.push_back(t0);
    }
    merged.end_time = end = sv.end_time;
  }
  // Peridigm's Verlet takes int(T/dt) whole steps and ends there: InitialDamage's 1e-2/2e-5
  // is 499.99999999999994 in floating point, and its gold's last output (every 50 steps)
  // is step 450, t = 0.009; ElasticPlasticCorrespondenceFullyPrescribedTension's
  // 1e-7/2e-9 = 49.999... steps end at 9.8e-8. Horizon's explicit solver takes
  // ceil(T/dt - 1e-9) whole steps (driver/check.cpp: 500 and 50 there), so the native deck
  // ends at int(T/dt) dt, where both codes take the same steps.
  // A Verlet stage after a static one takes int((T - t0)/dt) steps from t0 the same way
  // (Compression_QS_Explicit_3x2x2: (1e-4 - 5e-5)/1e-7 = 500.00000000000006, 500 steps).
  if (merged.method == "Verlet" && merged.fixed_dt) {
    const double steps = std::floor((merged.end_time - merged.start_time) / *merged.fixed_dt);
    if (steps >= 1) merged.end_time = merged.start_time + steps * *merged.fixed_dt;
  }
  if (merged.solver["type"].as<std::string>() == "static") {
    set_static_times(merged);
    // Each later QuasiStatic solver's start is written again (PredictorFromPreviousSolver's
    // golds: t = 0, 1, 1, 2); a staged run's static stage does not write it (not mapped).
    if (!merged.solver_starts.empty() && !merged.switch_to_verlet.IsMap()) {
      YAML::Node starts(YAML::NodeType::Sequence);
      starts.SetStyle(YAML::EmitterStyle::Flow);
      for (double t : merged.solver_starts) starts.push_back(number(t));
      merged.solver["solver_starts"] = starts;
    }
  } else
    merged.solver["end_time"] = number(merged.end_time);
  merged.static_stage = static_stage;
  // A QuasiStatic solver with Switch to Verlet: the static stage with on_failure: explicit,
  // then its Verlet fallback to the same Final Time (AdaptiveQuasiStaticSolver).
  if (merged.switch_to_verlet.IsMap()) {
    auto stage = std::make_shared<Solve>();
    stage->solver = YAML::Clone(merged.solver);
    stage->solver["on_failure"] = "explicit";
    stage->method = merged.method;
    stage->end_time = merged.end_time;
    stage->load_steps = merged.load_steps;
    stage->load_times = merged.load_times;
    set_static_times(*stage);
    Solve verlet;
    verlet.solver = YAML::Clone(merged.switch_to_verlet);
    verlet.solver["end_time"] = number(merged.end_time);
    verlet.method = "Verlet";
    verlet.start_time = verlet.end_time = merged.end_time;
    if (verlet.solver["time_step"]) verlet.fixed_dt = verlet.solver["time_step"].as<double>();
    verlet.static_stage = stage;
    verlet.switch_output_every = merged.switch_output_every;
    return verlet;
  }
  return merged;
}

// One output list (Output, Output1, ...): an Exodus file <Output Filename>.e with its own
// frequency (output.exodus_files). The first list also names the output directory and
// sets the VTU frames and history.csv's frequency.
void read_output_list(const DeckContext& ctx, const Item& o, const Solve& solve, bool first,
                      const std::set<std::string>* labels, YAML::Node& output, YAML::Node& exodus_files,
                      YAML::Node& history_columns) {
  MapReader om(ctx, o, {"Output File Type", "Output Format", "Output Filename", "Output Frequency", "Parallel Write",
                        "Output Variables", "Initial Output Step", "Final Output Step"});
  if (auto f = om.find("Output File Type")) {
    if (squash(read_string(ctx, *f)) != "exodusii")
      ctx.fail(f->mark, f->path + ": expected ExodusII, found " + text_of(*f));
  }
  if (auto f = om.find("Output Format")) read_string(ctx, *f);
  if (auto f = om.find("Parallel Write")) read_bool(ctx, *f);
  // Without an Output Filename the file is peridigm.e (Horizon's choice).
  const std::string name = om.find("Output Filename") ? read_string(ctx, *om.find("Output Filename")) : "peridigm";
  if (name.empty() || name.find('/') != std::string::npos)
    fail_expected(ctx, *om.find("Output Filename"), "a file name without folders");
  // A list that asks for global variables alone (and compute classes' labels) is
  // Peridigm's history file, <name>.h (MultipleOutputFiles2_gold.h, disk_impact's Output_2);
  // Horizon writes it in the same layout as the others.
  bool history_only = false;
  if (auto vars = om.find("Output Variables")) {
    history_only = true;
    for (const auto& e : map_entries(ctx, *vars)) {
      YAML::Node probe(YAML::NodeType::Sequence);
      const bool global = e.key == "Global_Kinetic_Energy" || add_global_column(e.key, probe) ||
                          (labels && labels->count(e.key));
      if (!global && e.value.node.IsScalar() && e.value.node.Scalar() != "false") history_only = false;
    }
  }
  const std::string file_name = name + (history_only ? ".h" : ".e");
  for (const auto& f : exodus_files)
    if (f["file"].as<std::string>() == file_name)
      ctx.fail(o.mark, o.path + ": a second output list writes '" + file_name + "'");
  int every = 1;
  if (auto f = om.find("Output Frequency")) {
    every = read_int(ctx, *f);
    if (every < 1) ctx.fail(f->mark, f->path + ": expected at least 1");
  }
  YAML::Node file;
  file["file"] = file_name;
  file["every"] = every;
  // Initial and Final Output Step bound the steps the list writes (the steps its
  // frequency divides): first_step, last_step. A staged run's steps count on from the
  // static stage's load steps (Compression_QS_Explicit_MultiFreqOutput: Final Output
  // Step 20 keeps the quasi-static file to its 20 load steps, Initial Output Step 21 the
  // explicit file to the Verlet steps, docs/peridigm.md).
  std::optional<int> first_step;
  if (auto it = om.find("Initial Output Step")) {
    first_step = read_int(ctx, *it);
    if (*first_step < 0) fail_expected(ctx, *it, "a step number >= 0");
    file["first_step"] = *first_step;
  }
  if (auto it = om.find("Final Output Step")) {
    const int last = read_int(ctx, *it);
    if (last < first_step.value_or(0))
      fail_expected(ctx, *it, "a step number >= the Initial Output Step (" + std::to_string(first_step.value_or(0)) + ")");
    file["last_step"] = last;
  }
  // Peridigm's Verlet reports at a prescribed component the prescribed rate plus
  // dt/2 (f + b)/rho (its second half-kick; ElasticBondBased2DPlaneStrain's gold to 3e-10):
  // the native `velocity: verlet` (docs/input.md).
  if (solve.method == "Verlet") file["velocity"] = "verlet";
  // Switch to Verlet's Output Frequency: each list's frequency once the run turned explicit.
  if (solve.switch_output_every > 0) file["explicit_every"] = solve.switch_output_every;
  exodus_files.push_back(file);
  if (first) {
    output["directory"] = "out/" + name;
    if (om.find("Output Frequency")) {
      output["history_every"] = every;
      if (solve.fixed_dt) {
        const double steps = std::ceil((solve.end_time - solve.start_time) / *solve.fixed_dt - 1e-9);
        output["frames"] = std::max(1, static_cast<int>(std::min(1e6, steps / every)));
      } else if (solve.solver["type"].as<std::string>() == "static") {
        output["frames"] = std::max(1, solve.load_steps / every);
      }
    }
  }
  std::vector<std::string> variables;  // the file's own variables beyond Horizon's set
  if (auto vars = om.find("Output Variables")) {
    // Horizon writes its own set of variables (driver/exodus_output.hpp) whatever the
    // list asks, and Lambda, Deformation_Gradient and compute classes' labels where asked;
    // a Peridigm variable it does not compute (Hourglass_Force_Density, ...) is left out
    // of the file, and a name one letter or two from a known one is a typo.
    static const std::vector<std::string> known = {
        "Displacement", "Velocity", "Acceleration", "Force", "Force_Density", "Damage", "Dilatation",
        "Weighted_Volume", "Volume", "Element_Id", "Block_Id", "Proc_Num", "Number_Of_Neighbors",
        "Stored_Elastic_Energy", "Stored_Elastic_Energy_Density", "Kinetic_Energy", "Global_Kinetic_Energy",
        "Model_Coordinates", "Coordinates", "Radius", "Horizon", "Lambda", "Equivalent_Plastic_Strain",
        "Nonlinear_Solver_Iterations", "Deformation_Gradient", "Contact_Force_Density", "Hourglass_Force_Density",
        "Left_Stretch_Tensor", "Rotation_Tensor", "Shape_Tensor_Inverse", "Unrotated_Rate_Of_Deformation",
        "Cauchy_Stress", "Unrotated_Cauchy_Stress", "Von_Mises_Stress", "Temperature", "Temperature_Change",
        "Flux_Divergence", "Velocity_Gradient", "Jacobian_Determinant", "Surface_Correction_Factor",
        "Dilatation_Normalization", "Deviatoric_Normalization",
        "Lagrange_Multiplier_Dilatation_1", "Lagrange_Multiplier_Dilatation_2", "Lagrange_Multiplier_Dilatation_3",
        "Lagrange_Multiplier_Dilatation_4", "Lagrange_Multiplier_Dilatation_5", "Lagrange_Multiplier_Dilatation_6",
        "Lagrange_Multiplier_Deviatoric_1", "Lagrange_Multiplier_Deviatoric_2", "Lagrange_Multiplier_Deviatoric_3",
        "Lagrange_Multiplier_Deviatoric_4", "Lagrange_Multiplier_Deviatoric_5", "Lagrange_Multiplier_Deviatoric_6"};
    for (const auto& e : map_entries(ctx, *vars)) {
      // The globals Peridigm writes become history columns under their own names (once,
      // whichever lists name them), and compute classes' Output Labels are written by
      // their columns.
      if (labels && labels->count(e.key)) {
        // ... and are the file's global variables too (WaveInBar_MultiBlock's Volume_Block_1).
        if (read_bool(ctx, e.value)) variables.push_back(e.key);
        continue;
      }
      YAML::Node global(YAML::NodeType::Sequence);
      if (add_global_column(e.key, global)) {
        bool have = false;
        for (const auto& c : history_columns) have = have || c["name"].as<std::string>() == global[0]["name"].as<std::string>();
        if (read_bool(ctx, e.value) && !have) history_columns.push_back(global[0]);
        continue;
      }
      // Peridigm also takes the components' names (Deformation_GradientXX, ...).
      const bool gradient = e.key.rfind("Deformation_Gradient", 0) == 0 &&
                            (e.key.size() == 20 || (e.key.size() == 22 && std::string("XYZ").find(e.key[20]) != std::string::npos &&
                                                    std::string("XYZ").find(e.key[21]) != std::string::npos));
      if (gradient) {
        if (read_bool(ctx, e.value) &&
            std::find(variables.begin(), variables.end(), "Deformation_Gradient") == variables.end())
          variables.push_back("Deformation_Gradient");
        continue;
      }
      // ... and the tensors' and vectors' of the models' fields (Left_Stretch_TensorXX,
      // Hourglass_Force_DensityX, ...): the whole variable is written.
      {
        auto component_of = [&](const std::string& base) {
          const std::string xyz = "XYZ";
          if (e.key.rfind(base, 0) != 0) return false;
          const std::string tail = e.key.substr(base.size());
          return (tail.size() == 1 || tail.size() == 2) &&
                 std::all_of(tail.begin(), tail.end(), [&](char ch) { return xyz.find(ch) != std::string::npos; });
        };
        const std::string* base = nullptr;
        for (const auto& v : model_field_variables())
          if (v != "Von_Mises_Stress" && v != "Equivalent_Plastic_Strain" && v != "Surface_Correction_Factor" &&
              component_of(v))
            base = &v;
        if (base) {
          if (read_bool(ctx, e.value) && std::find(variables.begin(), variables.end(), *base) == variables.end())
            variables.push_back(*base);
          continue;
        }
      }
      if (std::find(known.begin(), known.end(), e.key) == known.end()) {
        const auto near = closest_word(e.key, known);
        if (near && edit_distance(e.key, *near) <= 2)
          fail_choice(ctx, Item{YAML::Node(e.key), e.value.path, *e.value.key_mark, e.value.key_mark}, e.key, known,
                      "output variable");
      }
      // Lambda (elastic_plastic's plastic multiplier) and Deformation_Gradient are written
      // where asked (output.exodus_files' variables, driver/exodus_output.hpp).
      if (read_bool(ctx, e.value) && (e.key == "Lambda" || e.key == "Contact_Force_Density" || e.key == "Horizon" ||
                                      (e.key == "Flux_Divergence" && solve.method == "ImplicitDiffusion")))
        variables.push_back(e.key);
      // The models' fields under Peridigm's names (Hourglass_Force_Density, Cauchy_Stress,
      // ...; deck/exodus_variables.hpp), 0 at particles whose model has none.
      const auto& mf = model_field_variables();
      if (read_bool(ctx, e.value) && std::find(mf.begin(), mf.end(), e.key) != mf.end() &&
          std::find(variables.begin(), variables.end(), e.key) == variables.end())
        variables.push_back(e.key);
    }
  }
  if (variables.size()) {
    YAML::Node list(YAML::NodeType::Sequence);
    for (const auto& v : variables) list.push_back(v);
    exodus_files[exodus_files.size() - 1]["variables"] = list;
  }
}

}  // namespace

std::vector<std::string> deck_file_candidates(const std::string& folder, const std::string& name) {
  const fs::path given = name;
  if (given.is_absolute()) return {name};
  std::vector<std::string> out{(fs::path(folder) / given).string()};
  // Peridigm opens a relative name from the directory it runs in; its test scripts run
  // each deck from an npN/ folder below it (`cd np4; Peridigm ../deck.xml`), whose mesh
  // (np1/mesh.g, np4/mesh.g.4.i) the deck's folder does not hold.
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec) {
    const std::string there = (cwd / given).lexically_normal().string();
    if (there != fs::path(out[0]).lexically_normal().string()) out.push_back(there);
  }
  // "../x" from that npN/ folder is the deck's folder's x.
  auto part = given.begin();
  if (part != given.end() && *part == "..") {
    fs::path rest;
    for (++part; part != given.end(); ++part) rest /= *part;
    if (!rest.empty()) out.push_back((fs::path(folder) / rest).string());
  }
  return out;
}

std::string resolve_deck_file(const std::string& folder, const std::string& name) {
  const auto candidates = deck_file_candidates(folder, name);
  std::error_code ec;
  for (const auto& c : candidates)
    if (fs::exists(c, ec)) return c;
  return candidates.front();
}

bool is_peridigm_deck(const YAML::Node& root) {
  if (!root.IsMap() || root.size() != 1) return false;
  const YAML::Node& r = root;
  for (const auto& kv : r)
    if (kv.first.IsScalar() && kv.first.Scalar() == "Peridigm") return true;
  return false;
}

YAML::Node to_native(const YAML::Node& root, const std::string& file) {
  DeckContext ctx{file, 3, PlaneMode::none, nullptr};
  Translation t{ctx, fs::path(file).parent_path(), {}, 0, YAML::Node(YAML::NodeType::Map), std::nullopt,
                false, std::nullopt, std::nullopt, std::nullopt, false, "constant"};
  const Item top{root, "", root.Mark(), std::nullopt};
  MapReader outer(ctx, top, {"Peridigm"});
  const Item pd = outer.get("Peridigm", "the deck");
  // Peridigm reads each top-level list whose name starts with "Solver" as a solver and each
  // one whose name starts with "Output" as an output list (Solver1, Output_1, Output Data).
  std::vector<std::string> top_keys = {"Verbose", "Discretization", "Materials", "Damage Models", "Blocks",
                                       "Boundary Conditions", "Contact", "Compute Class Parameters", "Restart",
                                       "Multiphysics", "Enable Bond-Associated Hypoelastic Model",
                                       "Enable Bond-Associated Bond Associated Model"};
  std::vector<std::string> solver_keys, output_keys;
  for (const auto& e : map_entries(ctx, pd)) {
    if (e.key.rfind("Solver", 0) == 0) solver_keys.push_back(e.key), top_keys.push_back(e.key);
    if (e.key.rfind("Output", 0) == 0) output_keys.push_back(e.key), top_keys.push_back(e.key);
  }
  if (solver_keys.empty()) top_keys.push_back("Solver");  // for the missing-key error below
  MapReader m(ctx, pd, top_keys);
  if (solver_keys.empty()) m.get("Solver", "Initial Time, Final Time and one of Verlet, QuasiStatic, NOXQuasiStatic, Implicit");
  if (auto v = m.find("Verbose")) read_bool(ctx, *v);
  // Elastic Hypoelastic Correspondence runs its bond-associated form under this flag
  // (read_material). The np1/ and np4/ copies of ElasticBondAssociatedCorrespondence-
  // FullyPrescribedTension carry "Enable Bond-Associated Bond Associated Model", a flag no
  // Peridigm material reads (the copies' golds are the deck's without it): read, no effect.
  if (auto b = m.find("Enable Bond-Associated Hypoelastic Model")) t.bond_associated_hypoelastic = read_bool(ctx, *b);
  if (auto b = m.find("Enable Bond-Associated Bond Associated Model")) read_bool(ctx, *b);
  if (auto mp = m.find("Multiphysics"))
    ctx.fail(*mp->key_mark, mp->path + ": Peridigm's Multiphysics (a fluid pressure field coupled to the mechanics: "
                                       "Multiphysics Elastic, Solve For Pressure, Prescribed Fluid Pressure U) is not "
                                       "supported (docs/peridigm.md, \"Models and options not mapped yet\")");
  if (auto r = m.find("Restart")) {
    // Peridigm's Restart (Contact_Perforation_With_Restart's Run1, Run2): the run writes its
    // state at its end into ./restart-N/, and a later deck whose Initial Time is that end
    // continues from the newest such folder in the working directory. Horizon's checkpoints
    // (output.checkpoint, `horizon run DECK --restart FILE`; docs/input.md) continue the
    // same deck to its own end: written every N steps but not at the last, without Exodus
    // files, from t = 0 decks only. Read as a map; `Restart: false` has no effect.
    MapReader rm(ctx, *r, {"Restart"});
    const Item on = rm.get("Restart", "true or false");
    if (read_bool(ctx, on))
      ctx.fail(on.mark, on.path + ": Peridigm's restart (write the state at the end of this run into restart-N/, "
                                  "continued by another deck whose Initial Time is this run's Final Time) is not "
                                  "mapped: Horizon's checkpoints continue the same deck (output.checkpoint and `horizon "
                                  "run DECK --restart FILE`, docs/input.md), are not written at the last step and not "
                                  "with Exodus output; run the whole time span as one deck (Initial Time 0 to the "
                                  "last Final Time)");
  }

  // Blocks first: their horizons shape the discretisation checks. A group without its own
  // Horizon takes the Discretization's (Peridigm's older place for it: SurfaceFactorCube).
  const Item disc = m.get("Discretization", "Type: Text File or PdQuickGrid");
  MapReader d(ctx, disc,
              {"Type", "Input Mesh File", "NeighborhoodType", "TensorProduct3DMeshGenerator", "Influence Function",
               "Omit Bonds Between Blocks", "Bond Filters", "Horizon", "Compute Element-Horizon Intersections",
               "Element-Horizon Intersection Recursion Level", "Element-Horizon Intersection Number Of Samples"});
  const std::optional<Item> disc_horizon = d.find("Horizon");
  // Peridigm's element-horizon intersections (NeighborhoodVolume): each neighbour counted
  // by the part of its element inside the horizon sphere, found by sampling the element
  // recursively. Not mapped (Horizon's partial volumes are per lattice cell, docs/models.md
  // sec. 4); `false` has no effect, and the sampling keys are read with it.
  if (auto ci = d.find("Compute Element-Horizon Intersections"); ci && read_bool(ctx, *ci))
    ctx.fail(ci->mark, ci->path + ": Peridigm's element-horizon intersections (each neighbour's volume cut by the "
                                  "horizon sphere, sampled element by element) are not mapped; Horizon counts whole "
                                  "volumes for a mesh's particles");
  for (const char* k : {"Element-Horizon Intersection Recursion Level", "Element-Horizon Intersection Number Of Samples"})
    if (auto it = d.find(k)) read_int(ctx, *it);
  const Item blocks = m.get("Blocks", "a map of block groups {Block Names, Material, Horizon}");
  struct Group {
    std::string name;
    std::vector<std::string> block_names;
    Item names_item;
    std::string material, damage;
    Item material_item;
    std::optional<Item> damage_item;
    std::optional<double> horizon;  // the group's horizon; unset: an expression in x, y, z
    std::string horizon_text;       // the expression (muParser), when it varies in space
    Item horizon_item;
  };
  std::vector<Group> groups;
  for (const auto& e : map_entries(ctx, blocks)) {
    MapReader b(ctx, e.value, {"Block Names", "Material", "Damage Model", "Horizon"});
    Group g{e.key, {}, b.get("Block Names", "e.g. \"block_1 block_2\" or default"), "", "",
            b.get("Material", "the name of one of the Materials"), b.find("Damage Model"), std::nullopt, "", Item{}};
    std::istringstream names(read_string(ctx, g.names_item));
    for (std::string w; names >> w;) g.block_names.push_back(w);
    g.material = read_string(ctx, g.material_item);
    if (g.damage_item) g.damage = read_string(ctx, *g.damage_item);
    // Each group its own horizon (a number, or an expression in x, y, z: Peridigm's
    // variable horizon); groups of different horizons become bodies with their own
    // (docs/input.md "Bodies of different horizons"), bonded as Peridigm's directed lists.
    const std::optional<Item> own = b.find("Horizon");
    const Item h = own ? *own : disc_horizon ? *disc_horizon : b.get("Horizon", "the horizon of these blocks");
    g.horizon_item = h;
    if (h.node.IsScalar() && whole_number_text(h.node.Scalar())) {
      g.horizon = read_positive(ctx, h);
    } else {
      g.horizon_text = read_value(t, h);
      if (mentions_t(g.horizon_text))
        ctx.fail(h.mark, h.path + ": a horizon is a function of x, y, z (the reference position), not of t");
      t.several_horizons = true;
    }
    if (g.horizon && t.horizon_item && *g.horizon != t.horizon) t.several_horizons = true;
    if (g.horizon && (!t.horizon_item || *g.horizon > t.horizon)) t.horizon = *g.horizon;
    if (!t.horizon_item || g.horizon) t.horizon_item = h;
    groups.push_back(std::move(g));
  }
  if (groups.empty()) ctx.fail(blocks.mark, "Blocks: expected at least one block group");

  // Discretization.
  if (auto bf = d.find("Bond Filters")) add_precracks(t, read_bond_filters(ctx, *bf));
  const Item type = d.get("Type", "Text File or PdQuickGrid");
  const std::string kind = squash(read_string(ctx, type));
  ExodusDiscretization exodus;  // its node sets and block names, for Type Exodus
  std::string influence = "constant";
  if (auto f = d.find("Influence Function")) {
    const std::string w = squash(read_string(ctx, *f));
    if (w == "one" || w == "1" || w == "1.0") {
      influence = "constant";
    } else if (w == "1.0/zeta" || w == "1/zeta") {
      // omega = 1/|xi|: Horizon's inverse_length (its inverse is delta/|xi|, whose weighted
      // volume, an output, is delta times Peridigm's: Compression_3x1x1_InfluenceFunction).
      influence = "inverse_length";
    } else {
      ctx.fail(f->mark, f->path + ": expected One or \"1.0/zeta\" (the influence functions Horizon maps), found " +
                            text_of(*f));
    }
  }
  t.influence = influence;
  if (auto o = d.find("Omit Bonds Between Blocks")) {
    const std::string w = squash(read_string(ctx, *o));
    if (w == "all") t.out["bonds_between_bodies"] = false;  // each block bonded to itself alone
    else if (w != "none") fail_choice(ctx, *o, read_string(ctx, *o), {"None", "All"}, "Omit Bonds Between Blocks value");
  }
  if (kind == "textfile") {
    for (const char* k : {"NeighborhoodType", "TensorProduct3DMeshGenerator"})
      if (auto it = d.find(k)) ctx.fail(*it->key_mark, it->path + ": applies to Type PdQuickGrid only");
    read_text_file(t, d.get("Input Mesh File", "the text file of 'x y z block volume' rows"));
  } else if (kind == "pdquickgrid") {
    if (auto it = d.find("Input Mesh File")) ctx.fail(*it->key_mark, it->path + ": applies to Type Text File only");
    const Item gen = d.get("TensorProduct3DMeshGenerator", "the grid: origins, lengths and numbers of points");
    const Grid grid = read_grid(t, gen);
    bool spherical = false;
    if (auto n = d.find("NeighborhoodType")) {
      const std::string w = squash(read_string(ctx, *n));
      if (w != "spherical") ctx.fail(n->mark, n->path + ": expected Spherical, found " + text_of(*n));
      spherical = true;
    }
    if (!spherical) box_neighbourhood(t, grid);
    fill_grid(t, grid);
  } else if (kind == "exodus") {
    for (const char* k : {"NeighborhoodType", "TensorProduct3DMeshGenerator"})
      if (auto it = d.find(k)) ctx.fail(*it->key_mark, it->path + ": applies to Type PdQuickGrid only");
    exodus = read_exodus_discretization(ctx, d.get("Input Mesh File", "the Exodus mesh (.g)"), t.folder.string());
    for (const auto& p : exodus.points) t.points.push_back({p.x, p.volume, p.block});
  } else {
    fail_choice(ctx, type, read_string(ctx, type), {"Text File", "PdQuickGrid", "Exodus"}, "discretisation");
  }

  // Materials and damage models, by name.
  std::map<std::string, Item> materials, damages;
  for (const auto& e : map_entries(ctx, m.get("Materials", "a map of materials"))) materials.emplace(e.key, e.value);
  if (auto dm = m.find("Damage Models"))
    for (const auto& e : map_entries(ctx, *dm)) damages.emplace(e.key, e.value);
  std::vector<std::string> material_names, damage_names;
  for (const auto& [k, v] : materials) material_names.push_back(k);
  for (const auto& [k, v] : damages) damage_names.push_back(k);

  // One native material per block group (its material with its damage model).
  YAML::Node mats(YAML::NodeType::Map);
  std::map<int, std::string> group_of_block;  // block id -> group
  std::set<int> present;
  for (const auto& p : t.points) present.insert(p.block);
  for (const auto& g : groups) {
    check_reference(ctx, g.material_item, g.material, material_names, "material");
    // The group's own horizon while its material is read (the planar micromodulus reads it;
    // 0: one that varies in space).
    const double largest = t.horizon;
    t.horizon = g.horizon ? *g.horizon : 0;
    YAML::Node mat = read_material(t, materials.at(g.material));
    t.horizon = largest;
    if (mat["model"]) mat["influence"] = influence;  // (a Diffusion material has no mechanics)
    if (!mat["model"] && g.damage_item)
      ctx.fail(g.damage_item->mark, g.damage_item->path + ": a block of a Diffusion material has no mechanics to damage");
    if (g.damage_item) {
      check_reference(ctx, *g.damage_item, g.damage, damage_names, "damage model");
      const YAML::Node damage = read_damage(t, damages.at(g.damage));
      same_damage_expansion(t, damages.at(g.damage), mat);
      if (!damage.IsNull()) mat["damage"] = damage;
      else if (groups.size() > 1)
        // Horizon's precracks cut the bonds of every body alike.
        ctx.fail(g.damage_item->mark, g.damage_item->path + ": an Initial Damage model is read for decks of one block "
                                                            "group only (its filters apply to every block in Horizon)");
    }
    mats[g.name] = mat;
    for (const auto& bn : g.block_names) {
      std::vector<int> ids;
      if (bn == "default") {
        // Peridigm's default group takes the blocks no other group names.
        for (int id : present) {
          bool named = false;
          for (const auto& other : groups)
            for (const auto& w : other.block_names) {
              int k = w.rfind("block_", 0) == 0 ? std::atoi(w.c_str() + 6) : 0;
              if (auto nm = exodus.block_names.find(w); k < 1 && nm != exodus.block_names.end()) k = nm->second;
              named = named || k == id;
            }
          if (!named) ids.push_back(id);
        }
      } else {
        int id = 0;
        if (bn.rfind("block_", 0) == 0) id = std::atoi(bn.c_str() + 6);
        if (auto named = exodus.block_names.find(bn); id < 1 && named != exodus.block_names.end()) id = named->second;
        if (id < 1)
          ctx.fail(g.names_item.mark, g.names_item.path + ": expected block names block_1, block_2, ... or default, "
                                                           "found '" + bn + "'");
        if (!present.count(id))
          ctx.fail(g.names_item.mark, g.names_item.path + ": the discretisation has no points in " + bn);
        ids.push_back(id);
      }
      for (int id : ids) {
        if (group_of_block.count(id))
          ctx.fail(g.names_item.mark, fmt::format("{}: block_{} is already in block group '{}'", g.names_item.path,
                                                  id, group_of_block[id]));
        group_of_block[id] = g.name;
      }
    }
  }
  for (int id : present)
    if (!group_of_block.count(id))
      ctx.fail(blocks.mark, fmt::format("Blocks: block_{} of the discretisation is in no block group", id));

  // Blocks of different horizons: the deck's horizon is the largest at any point (the
  // search radius), and each body whose group has another gets its own (a number, or the
  // expression in x, y, z the engine evaluates at each particle).
  std::map<std::string, const Group*> group_named;
  for (const auto& g : groups) group_named[g.name] = &g;
  if (t.several_horizons) {
    double largest = 0;
    std::map<std::string, Expression> compiled;
    for (const auto& p : t.points) {
      const Group& g = *group_named.at(group_of_block.at(p.block));
      double v = 0;
      if (g.horizon) {
        v = *g.horizon;
      } else {
        auto it = compiled.find(g.name);
        if (it == compiled.end()) it = compiled.emplace(g.name, Expression(g.horizon_text)).first;
        v = it->second(0, p.x.x, p.x.y, p.x.z);
        if (!(v > 0) || !std::isfinite(v))
          ctx.fail(g.horizon_item.mark, fmt::format("{}: the horizon is {} at the point ({}, {}, {}) of block_{}; "
                                                    "expected > 0", g.horizon_item.path, v, p.x.x, p.x.y, p.x.z, p.block));
      }
      largest = std::max(largest, v);
    }
    t.horizon = largest;
  }

  // The lattice keys Horizon needs: the spacing only bounds the horizon from below
  // for listed points (each point keeps its own volume); its smallest cube root.
  double spacing = 1e300;
  for (const auto& p : t.points) spacing = std::min(spacing, std::cbrt(p.volume));
  spacing = std::min(spacing, t.horizon);
  YAML::Node& out = t.out;
  out["dimension"] = 3;
  out["spacing"] = number(spacing);
  out["horizon"] = number(t.horizon);
  out["materials"] = mats;
  YAML::Node bodies(YAML::NodeType::Sequence);
  for (int id : present) {
    YAML::Node body;
    body["name"] = fmt::format("block_{}", id);
    body["material"] = group_of_block[id];
    if (const Group& g = *group_named.at(group_of_block[id]); t.several_horizons && (!g.horizon || *g.horizon != t.horizon))
      body["horizon"] = g.horizon ? number(*g.horizon) : YAML::Node(g.horizon_text);
    YAML::Node rows(YAML::NodeType::Sequence);
    for (const auto& p : t.points)
      if (p.block == id) rows.push_back(point_row(p.x, p.volume));
    body["shape"]["points"] = rows;
    bodies.push_back(body);
  }
  out["bodies"] = bodies;

  // Boundary conditions: node sets are the non-map entries; the rest are conditions.
  YAML::Node regions(YAML::NodeType::Map), ics(YAML::NodeType::Sequence), loads(YAML::NodeType::Sequence);
  // Prescribed and Initial Temperature conditions (the native thermal section, below).
  struct TemperatureCond {
    std::string set, value;
    bool initial;
    Item item;
  };
  std::vector<TemperatureCond> temperatures;
  std::optional<ComputeClasses> computes;  // Compute Class Parameters (compute_classes.cpp)
  const auto compute_item = m.find("Compute Class Parameters");
  if (auto bc = m.find("Boundary Conditions")) {
    std::map<std::string, std::vector<int>> sets = exodus.node_sets;  // an Exodus mesh's, then the deck's
    const auto entries = map_entries(ctx, *bc);
    std::map<std::string, Item> set_items;  // the deck's own lists (an Exodus mesh's are 1-based)
    for (const auto& e : entries) {
      if (e.value.node.IsMap()) continue;
      if (e.key == "Create Node Set For Rank Deficient Nodes")
        ctx.fail(*e.value.key_mark, e.value.path + ": not supported (Horizon's static solver pins no points itself)");
      sets[e.key] = read_ids(t, e.value);
      set_items.emplace(e.key, e.value);
    }
    number_from_one(t, sets, set_items);
    std::vector<std::string> set_names;
    for (const auto& [k, v] : sets) set_names.push_back(k);
    std::set<std::string> used;
    // Per node set and kind, the components given so far (one native entry each).
    struct Cond {
      std::string set, kind;
      std::array<std::optional<std::string>, 3> value;
    };
    std::vector<Cond> conds;
    for (const auto& e : entries) {
      if (!e.value.node.IsMap()) continue;
      MapReader c(ctx, e.value, {"Type", "Node Set", "Coordinate", "Value"});
      const Item type_item = c.get("Type", "Prescribed Displacement, Initial Velocity, ...");
      const std::string w = squash(read_string(ctx, type_item));
      if (w == "prescribedtemperature" || w == "initialtemperature") {
        // A scalar field: no Coordinate (temperature_conditions, below).
        if (auto k = c.find("Coordinate"))
          ctx.fail(*k->key_mark, k->path + ": a temperature condition has no Coordinate");
        const Item set_item = c.get("Node Set", "the name of a node set defined in Boundary Conditions");
        const std::string set = read_string(ctx, set_item);
        check_reference(ctx, set_item, set, set_names, "node set");
        const Item value = c.get("Value", "a number or an expression in x, y, z, t");
        temperatures.push_back({set, read_value(t, value), w == "initialtemperature", value});
        if (w == "prescribedtemperature") used.insert(set);
        continue;
      }
      std::string kind;
      if (w == "prescribeddisplacement") kind = "displacement";
      else if (w == "initialdisplacement") kind = "initial_displacement";
      else if (w == "initialvelocity") kind = "initial_velocity";
      else if (w == "bodyforce") kind = "body_force";
      else
        fail_choice(ctx, type_item, read_string(ctx, type_item),
                    {"Prescribed Displacement", "Initial Displacement", "Initial Velocity", "Body Force",
                     "Prescribed Temperature", "Initial Temperature"},
                    "boundary condition Horizon reads");
      const Item set_item = c.get("Node Set", "the name of a node set defined in Boundary Conditions");
      const std::string set = read_string(ctx, set_item);
      check_reference(ctx, set_item, set, set_names, "node set");
      used.insert(set);
      const Item coord = c.get("Coordinate", "x, y or z");
      const int axis = static_cast<int>(choose_word(ctx, coord, {"x", "y", "z"}));
      std::string value = read_value(t, c.get("Value", "a number or an expression in x, y, z, t"));
      if (kind == "body_force" && !mentions_t(value)) {
        // Peridigm evaluates a Body Force at each step's time, so one without t acts in
        // full from t = 0 (CentrifugalLoad's gold has it in its t = 0 output); Horizon's
        // static solver ramps a load written without t (docs/input.md, "Static
        // solves") and takes one written in t as written. Explicit runs: the same force.
        value = "(" + value + ") + 0*t";
      }
      auto it = std::find_if(conds.begin(), conds.end(),
                             [&](const Cond& k) { return k.set == set && k.kind == kind; });
      if (it == conds.end()) {
        conds.push_back({set, kind, {}});
        it = conds.end() - 1;
      }
      if (it->value[axis])
        ctx.fail(coord.mark, e.value.path + ": node set '" + set + "' already has a " + type_item.node.Scalar() +
                                 " along " + coord.node.Scalar());
      it->value[axis] = value;
    }
    if (compute_item) {
      computes = read_compute_classes(ctx, *compute_item, set_names, present);
      used.insert(computes->node_sets.begin(), computes->node_sets.end());
    }
    // Initial Temperature over the whole body is thermal.initial_temperature.
    for (const auto& k : temperatures)
      if (k.initial) {
        std::set<int> ids(sets[k.set].begin(), sets[k.set].end());
        if (ids.size() != t.points.size())
          ctx.fail(k.item.mark, k.item.path + ": an Initial Temperature is read for a node set that holds every "
                                              "point (Horizon's thermal.initial_temperature); '" + k.set +
                                              "' holds " + std::to_string(ids.size()) + " of " +
                                              std::to_string(t.points.size()));
        if (mentions_t(k.value)) ctx.fail(k.item.mark, k.item.path + ": an initial temperature in t");
      }
    for (const auto& set : used) {
      YAML::Node rows(YAML::NodeType::Sequence);
      for (int id : sets[set]) rows.push_back(point_row(t.points[static_cast<std::size_t>(id - 1)].x, std::nullopt));
      regions[set]["points"] = rows;
    }
    for (const auto& k : conds) {
      const bool free_rest = k.kind == "displacement" || k.kind == "initial_displacement" || k.kind == "initial_velocity";
      YAML::Node v(YAML::NodeType::Sequence);
      v.SetStyle(YAML::EmitterStyle::Flow);
      for (int a = 0; a < 3; ++a) {
        if (k.value[a]) v.push_back(*k.value[a]);
        else if (free_rest) v.push_back(YAML::Node(YAML::NodeType::Null));
        else v.push_back(0);
      }
      YAML::Node entry;
      entry["region"] = k.set;
      if (k.kind == "initial_velocity") {
        entry["velocity"] = v;
        ics.push_back(entry);
      } else if (k.kind == "initial_displacement") {
        entry["displacement"] = v;
        ics.push_back(entry);
      } else {
        entry[k.kind] = v;
        loads.push_back(entry);
      }
    }
  }
  if (compute_item && !computes) computes = read_compute_classes(ctx, *compute_item, {}, present);
  // A temperature field: Peridigm's Temperature, 0 unless an Initial Temperature or a
  // Prescribed Temperature sets it, prescribed without conduction (thermal.conduction:
  // false) where no Diffusion material conducts it; it strains the materials with a
  // Thermal Expansion Coefficient (read_material).
  bool expands = false;
  for (const auto& mt : mats) expands = expands || (mt.second["model"] && mt.second["thermal"]);
  // Diffusion materials conduct (heat alone: Horizon's solver.type heat, docs/peridigm.md).
  const bool diffusion = t.diffusion_item.has_value();
  if (diffusion && t.mechanical_item)
    ctx.fail(t.mechanical_item->mark, t.mechanical_item->path + ": a mechanical material in a deck with a Diffusion "
                                                                "material (heat and mechanics in one run, Peridigm's "
                                                                "Multiphysics) is not supported");
  if (expands || !temperatures.empty() || diffusion) {
    YAML::Node thermal;
    if (!diffusion) thermal["conduction"] = false;
    thermal["initial_temperature"] = 0;
    if (diffusion && t.improved_quadrature.value_or(false)) thermal["quadrature"] = "improved";
    for (const auto& k : temperatures) {
      if (k.initial) {
        thermal["initial_temperature"] = k.value;
        continue;
      }
      YAML::Node bc;
      bc["region"] = k.set;
      bc["temperature"] = k.value;
      thermal["boundary"].push_back(bc);
    }
    for (auto mt : mats)
      if (!mt.second["thermal"]) mt.second["thermal"]["expansion"] = 0;
    out["thermal"] = thermal;
  }
  if (auto c = m.find("Contact")) out["contact"] = read_contact_section(ctx, *c, t.horizon, present);
  if (regions.size()) out["regions"] = regions;
  if (ics.size()) out["initial_conditions"] = ics;
  if (loads.size()) out["loads"] = loads;

  // Solvers: Peridigm runs every top-level list whose name starts with "Solver" in turn
  // (Solver1, Solver2, ...); Horizon runs one solver a deck, so consecutive solvers that
  // are one run cut in pieces (the same method and options, each starting where the last
  // ended, with the same step) become that one run (read_solvers).
  const Solve solve = read_solvers(ctx, solver_keys, m);
  // Peridigm's Verlet moves a prescribed point by the change of its function since the
  // start, u = g(t) - g(0) (DeformationGradient_PlaneStrainCompression's gold: DisplacementX
  // = x (e^(0.0953 t/1e-8) - 1) for its value x exp(0.0953 t/1e-8), within 4e-19 at every
  // point and step, 0 at t = 0). The importer's Verlet runs with `verlet: peridigm`
  // (read_solvers), whose drift moves a prescribed point by g(t1) - g(t0) each step from its
  // initial state, so g(0) is never applied and the text of g stays as the deck wrote it.
  if (loads.size()) out["loads"] = loads;
  if (diffusion && solve.method != "ImplicitDiffusion")
    ctx.fail(t.diffusion_item->mark, t.diffusion_item->path + ": a Diffusion material runs with the ImplicitDiffusion "
                                                               "solver only (this deck's is " + solve.method + ")");
  if (!diffusion && solve.method == "ImplicitDiffusion")
    ctx.fail(m.find(solver_keys.front())->mark, solver_keys.front() + ": the ImplicitDiffusion solver needs a "
                                                                      "Diffusion material");
  if (diffusion) out["thermal"]["integration"] = "steady";
  if (solve.static_stage) {
    // Peridigm's QuasiStatic solver, then Verlet: the native list of two stages.
    YAML::Node stages(YAML::NodeType::Sequence);
    stages.push_back(solve.static_stage->solver);
    stages.push_back(solve.solver);
    out["solver"] = stages;
  } else {
    out["solver"] = solve.solver;
  }

  // Output: each top-level list whose name starts with "Output" (Output, Output1,
  // Output_1, Output Data, ...) is one Exodus file with its own frequency.
  YAML::Node output;
  YAML::Node history_columns(YAML::NodeType::Sequence);
  YAML::Node exodus_files(YAML::NodeType::Sequence);
  output["directory"] = "out/peridigm";
  for (std::size_t k = 0; k < output_keys.size(); ++k)
    read_output_list(ctx, *m.find(output_keys[k]), solve, k == 0, computes ? &computes->labels : nullptr, output,
                     exodus_files, history_columns);
  if (exodus_files.size()) output["exodus_files"] = exodus_files;
  if (computes)
    for (const auto& col : computes->columns) history_columns.push_back(col);
  if (history_columns.size()) output["history_columns"] = history_columns;
  out["output"] = output;
  return out;
}

std::string native_yaml(const YAML::Node& native, const std::string& source) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << native;
  return "# Converted by `horizon convert` from the Peridigm deck " + source + "\n" + std::string(e.c_str()) + "\n";
}

}  // namespace horizon::peridigm
