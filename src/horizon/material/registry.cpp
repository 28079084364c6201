// The material models Horizon knows, one line each (docs/design.md, "Adding a material
// model"). The deck accepts these names after `model:`; docs/models.md has a page for each.
#include "horizon/material/model.hpp"
#include "horizon/material/models/bond_associated.hpp"
#include "horizon/material/models/bond_pair.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/material/models/elastic_plastic.hpp"
#include "horizon/material/models/extended_correspondence.hpp"
#include "horizon/material/models/linear_lps.hpp"
#include "horizon/material/models/lps.hpp"
#include "horizon/material/models/microplastic.hpp"
#include "horizon/material/models/nonlinear_solid.hpp"
#include "horizon/material/models/pals.hpp"
#include "horizon/material/models/pmb.hpp"
#include "horizon/material/models/viscoelastic.hpp"

namespace horizon {

const std::vector<ModelEntry>& model_registry() {
  static const std::vector<ModelEntry> registry = {
      pmb_model(),
      lps_model(),
      nonlinear_solid_model(),
      elastic_plastic_model(),
      viscoelastic_model(),
      correspondence_model(),
      extended_correspondence_model(),
      bond_associated_model(),
      microplastic_model(),
      bond_pair_model(),
      pals_model(),
      linear_lps_model(),
  };
  return registry;
}

}  // namespace horizon
