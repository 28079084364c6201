#include "horizon/deck/thermal.hpp"

#include "horizon/deck/conditions.hpp"

namespace horizon::deck {

ThermalMaterialConfig read_thermal_material(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item,
              {"conductivity", "specific_heat", "expansion", "reference_temperature", "plastic_heat_fraction",
               "critical_stretch_slope"});
  ThermalMaterialConfig t;
  t.enabled = true;
  // Both required when the thermal section conducts (check_thermal, deck.cpp): a prescribed
  // temperature field (thermal.conduction: false) needs neither.
  if (auto k = m.find("conductivity")) t.conductivity = read_positive(ctx, *k);
  if (auto c = m.find("specific_heat")) t.specific_heat = read_positive(ctx, *c);
  if (auto a = m.find("expansion")) t.expansion = read_number(ctx, *a);
  if (auto r = m.find("reference_temperature")) {
    // `initial`: each particle's own temperature at t = 0 (Peridigm's Temperature_Change).
    if (r->node.IsScalar() && r->node.Scalar() == "initial") t.reference_initial = true;
    else t.reference_temperature = read_number(ctx, *r);
  }
  if (auto c = m.find("critical_stretch_slope")) t.critical_stretch_slope = read_number(ctx, *c);
  if (!m.has("reference_temperature") && (t.expansion != 0 || t.critical_stretch_slope != 0)) {
    m.fail_missing("reference_temperature",
                   "the temperature of no thermal strain and of the given critical stretch [K] (expansion or "
                   "critical_stretch_slope is not 0)");
  }
  // Taylor and Quinney's fraction of plastic work turned to heat: 0.9 for metals.
  t.plastic_heat_fraction = 0.9;
  if (auto b = m.find("plastic_heat_fraction")) {
    const double v = read_number(ctx, *b);
    if (!(v >= 0 && v <= 1)) fail_expected(ctx, *b, "a fraction in [0, 1]");
    t.plastic_heat_fraction = v;
  }
  return t;
}

namespace {

ThermalBoundaryConfig read_boundary(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions) {
  MapReader m(ctx, item, {"region", "temperature", "flux", "convection", "normal"});
  ThermalBoundaryConfig bc;
  const std::string kind = *m.exactly_one({"temperature", "flux", "convection"}, true);
  bc.region = read_region_name(ctx, m.get("region", "where the condition acts: a name from regions, or all"), regions);
  if (kind == "temperature") {
    bc.kind = ThermalBoundaryKind::temperature;
    bc.value = read_scalar_expr(ctx, *m.find(kind));
  } else if (kind == "flux") {
    bc.kind = ThermalBoundaryKind::flux;
    bc.value = read_scalar_expr(ctx, *m.find(kind));
  } else {
    bc.kind = ThermalBoundaryKind::convection;
    MapReader c(ctx, *m.find(kind), {"coefficient", "ambient"});
    bc.coefficient = read_non_negative(ctx, c.get("coefficient", "the film coefficient h [W/(m^2 K)], >= 0"));
    bc.ambient = read_scalar_expr(ctx, c.get("ambient", "the ambient temperature [K] (number or expression)"));
  }
  if (auto n = m.find("normal")) {
    if (bc.kind == ThermalBoundaryKind::temperature)
      ctx.fail(*n->key_mark, n->path + ": 'normal' applies to flux and convection only, not to temperature");
    const std::vector<std::string> axes = {"x", "y", "z"};
    bc.normal_axis =
        static_cast<int>(choose_word(ctx, *n, std::vector<std::string>(axes.begin(), axes.begin() + ctx.dimension)));
  }
  return bc;
}

}  // namespace

ThermalConfig read_thermal(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions) {
  MapReader m(ctx, item,
              {"initial_temperature", "kernel", "calibration", "integration", "quadrature", "time_scale", "conduction",
               "boundary"});
  ThermalConfig t;
  t.enabled = true;
  if (auto c = m.find("conduction")) t.conduction = read_bool(ctx, *c);
  t.initial_temperature =
      read_scalar_expr(ctx, m.get("initial_temperature", "the temperature at t = 0 [K] (number or expression in x, y, z)"));
  if (auto k = m.find("kernel"))
    t.kernel = read_enum<HeatKernel>(ctx, *k, {{"inverse", HeatKernel::inverse}, {"constant", HeatKernel::constant}});
  if (auto c = m.find("calibration"))
    t.calibration = read_enum<HeatCalibration>(
        ctx, *c, {{"continuum", HeatCalibration::continuum}, {"discrete", HeatCalibration::discrete}});
  if (auto i = m.find("integration"))
    t.integration = read_enum<HeatIntegration>(
        ctx, *i,
        {{"explicit", HeatIntegration::explicit_euler}, {"implicit", HeatIntegration::implicit_euler},
         {"steady", HeatIntegration::steady}});
  if (auto q = m.find("quadrature")) {
    t.quadrature =
        read_enum<HeatQuadrature>(ctx, *q, {{"one_point", HeatQuadrature::one_point}, {"improved", HeatQuadrature::improved}});
    // The improved weights make the sum exact on quadratics against the horizon integral:
    // kappa is the continuum one (the discrete moment would calibrate the rule they replace).
    if (auto c = m.find("calibration");
        c && t.quadrature == HeatQuadrature::improved && t.calibration == HeatCalibration::discrete)
      ctx.fail(c->mark, c->path + ": quadrature: improved is exact on quadratics over the whole horizon, so it takes "
                                  "calibration: continuum (the default)");
  }
  if (auto s = m.find("time_scale")) t.time_scale = read_positive(ctx, *s);
  if (auto b = m.find("boundary"))
    for (const auto& i : read_list(ctx, *b)) {
      t.boundary.push_back(read_boundary(ctx, i, regions));
      // Without conduction no heat flows in: only temperatures can be prescribed.
      if (!t.conduction && t.boundary.back().kind != ThermalBoundaryKind::temperature)
        ctx.fail(i.mark, i.path + ": flux and convection need conduction; with thermal.conduction: false the "
                                  "boundary prescribes temperatures only");
    }
  if (!t.conduction) {
    for (const char* k : {"kernel", "calibration", "integration", "quadrature", "time_scale"})
      if (auto it = m.find(k))
        ctx.fail(*it->key_mark, it->path + ": a setting of the heat conduction; this section has conduction: false");
  }
  return t;
}

}  // namespace horizon::deck
