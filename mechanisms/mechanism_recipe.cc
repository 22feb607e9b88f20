// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/mechanism_recipe.h"

#include <stdexcept>

namespace flexrod {

// Defined in mechanisms/recipe_<name>.cc, one per recipe.
const MechanismRecipe& SliderCrankRecipe();
const MechanismRecipe& PendulumRecipe();

namespace {

std::vector<const MechanismRecipe*> Recipes() { return {&SliderCrankRecipe(), &PendulumRecipe()}; }

}  // namespace

const MechanismRecipe& FindRecipe(const std::string& type) {
  for (const MechanismRecipe* r : Recipes()) {
    if (type == r->name()) return *r;
  }
  // The schema's choices of mechanism.type are RecipeNames(): any other value is refused on input.
  throw std::logic_error("no mechanism recipe named \"" + type + "\"");
}

std::vector<std::string> RecipeNames() {
  std::vector<std::string> names;
  for (const MechanismRecipe* r : Recipes()) names.emplace_back(r->name());
  return names;
}

}  // namespace flexrod
