// tests/mechanisms/clearance_config_test.cc — the clearance joint from input keys
// (mechanisms/joint_config.h) and its place in the slider-crank (mechanisms/mechanism_model.h): the
// schema offers every normal law of the contact layer; defaults give the rig's joint (R_bush =
// 9.525 mm, c = 0.5 mm, R_pin = 9.025 mm, L = 12.7 mm, steel, hybrid, Coulomb μ = 0.18) with a
// resolved record; every bad input fails with an InputError naming the joint.* key; the built
// slider-crank carries the joint as a force element between the bush and the journal, starts
// concentric and has a consistent initial state; its ideal twin has none.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/error.h"
#include "contact/normal_law.h"
#include "input/config.h"
#include "input/presets.h"
#include "mechanisms/joint_config.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/clearance_joint.h"
#include "multibody/simulate.h"

namespace flexrod {
namespace {

/// The rigid rig with the schema's joint defaults (the preset's own joint keys left out).
Config Rigid(std::initializer_list<std::string> sets) {
  Config cfg;
  cfg.Set("rod.type", "rigid");
  cfg.Set("rod.length", "300 mm");
  cfg.Set("crank.length", "50 mm");
  cfg.Set("slider.mass", "1.02 kg");
  cfg.Set("joint.type", "clearance");
  for (const std::string& s : sets) cfg.SetAssignment(s);
  return cfg;
}

const contact::ResolvedParameter* Find(const ClearanceJointConfig& jc, const std::string& name) {
  for (const auto& p : jc.parameters) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

/// Expects an InputError whose key is `key`; returns its rule.
template <typename Fn>
std::string ExpectInputError(Fn&& fn, const std::string& key) {
  try {
    fn();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
    return e.rule();
  }
  ADD_FAILURE() << "no InputError for " << key;
  return "";
}

TEST(ClearanceConfig, SchemaOffersExactlyTheNormalLawsOfTheContactLayer) {
  const ParamDef* law = FindParam("joint.law");
  ASSERT_NE(law, nullptr);
  EXPECT_EQ(law->choices, contact::NormalLawNames());
  EXPECT_EQ(law->default_text, "hybrid");
}

TEST(ClearanceConfig, DefaultsAreTheRigJointWithARecordOfEveryParameter) {
  const ClearanceJointConfig jc = ResolveClearanceJoint(Rigid({}), 1.02);
  EXPECT_DOUBLE_EQ(jc.geometry.bush_radius, 9.525e-3);
  EXPECT_DOUBLE_EQ(jc.geometry.clearance(), 0.5e-3);
  EXPECT_NEAR(jc.geometry.pin_radius, 9.025e-3, 1e-15);
  EXPECT_DOUBLE_EQ(jc.geometry.length, 12.7e-3);
  EXPECT_DOUBLE_EQ(jc.materials.pin_youngs_modulus, 200e9);  // fem steel
  EXPECT_DOUBLE_EQ(jc.materials.restitution, contact::kDefaultRestitution);
  ASSERT_TRUE(std::holds_alternative<contact::HybridLaw>(jc.normal_law));
  ASSERT_TRUE(jc.friction_law.has_value());
  const auto& coulomb = std::get<contact::CoulombFrictionLaw>(*jc.friction_law);
  EXPECT_DOUBLE_EQ(coulomb.friction_coefficient, 0.18);
  // The record: SI values with units and sources, the law's stiffness among them.
  const auto* pin = Find(jc, "joint.pin_radius");
  ASSERT_NE(pin, nullptr);
  EXPECT_NEAR(pin->value, 9.025e-3, 1e-15);
  EXPECT_EQ(pin->unit, "m");
  EXPECT_EQ(pin->source, "derived");
  const auto* k = Find(jc, "joint.law.stiffness");
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->value, std::get<contact::HybridLaw>(jc.normal_law).hysteresis.stiffness);
  EXPECT_EQ(k->unit, "N/m^1.5");
  EXPECT_NE(Find(jc, "joint.friction_law.friction-coefficient"), nullptr);
  EXPECT_EQ(Find(jc, "joint.law.restitution")->source, "default");
}

TEST(ClearanceConfig, OverridesMaterialsAndFrictionReachTheLaws) {
  const ClearanceJointConfig jc =
      ResolveClearanceJoint(Rigid({"joint.law=hertz", "joint.stiffness=3e10", "joint.exponent=1.4",
                                   "joint.pin_material=brass", "joint.friction_law=lugre",
                                   "joint.friction=0.4", "joint.clearance=1 mm"}),
                            1.02);
  const auto& hertz = std::get<contact::HertzLaw>(jc.normal_law);
  EXPECT_EQ(hertz.stiffness, 3e10);
  EXPECT_EQ(hertz.exponent, 1.4);
  EXPECT_DOUBLE_EQ(jc.materials.pin_youngs_modulus, 97e9);  // fem brass
  EXPECT_DOUBLE_EQ(jc.geometry.pin_radius, 9.525e-3 - 1e-3);
  EXPECT_EQ(std::get<contact::LuGreFrictionLaw>(*jc.friction_law).friction_coefficient, 0.4);
  EXPECT_EQ(Find(jc, "joint.law.stiffness")->source, "input");

  // A law that calibrates damping to the restitution gets the slider mass by default.
  const ClearanceJointConfig kv = ResolveClearanceJoint(Rigid({"joint.law=kelvin-voigt"}), 1.02);
  const auto* m = Find(kv, "joint.law.effective-mass");
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->value, 1.02);
  EXPECT_EQ(m->source, "derived (slider.mass)");
  const ClearanceJointConfig none = ResolveClearanceJoint(Rigid({"joint.friction_law=none"}), 1.0);
  EXPECT_FALSE(none.friction_law.has_value());
}

TEST(ClearanceConfig, BadInputNamesTheJointKey) {
  auto resolve = [](std::initializer_list<std::string> sets) {
    return [sets] { ResolveClearanceJoint(Rigid(sets), 1.02); };
  };
  ExpectInputError(resolve({"joint.clearance=0 mm"}), "joint.clearance");
  ExpectInputError(resolve({"joint.clearance=-0.1 mm"}), "joint.clearance");
  const std::string pin = ExpectInputError(resolve({"joint.clearance=10 mm"}), "joint.clearance");
  EXPECT_NE(pin.find("pin radius"), std::string::npos) << pin;
  ExpectInputError(resolve({"joint.bush_radius=0 mm"}), "joint.bush_radius");
  ExpectInputError(resolve({"joint.length=0 mm"}), "joint.length");
  ExpectInputError(resolve({"joint.restitution=0"}), "joint.restitution");
  ExpectInputError(resolve({"joint.restitution=1.2"}), "joint.restitution");
  // A parameter the law does not take: contact's ParameterMap validation, re-keyed.
  const std::string rule =
      ExpectInputError(resolve({"joint.law=hertz", "joint.damping=5 N s/m"}), "joint.damping");
  EXPECT_NE(rule.find("does not take"), std::string::npos) << rule;
  // Hertz is elastic: a restitution given to it is refused; its default (a resolved input
  // lists it) is not.
  ExpectInputError(resolve({"joint.law=hertz", "joint.restitution=0.5"}), "joint.restitution");
  EXPECT_NO_THROW(resolve({"joint.law=hertz", "joint.restitution=0.9"})());
  ExpectInputError(resolve({"joint.exponent=0.5"}), "joint.exponent");
  ExpectInputError(resolve({"joint.stiffness=-1"}), "joint.stiffness");
  ExpectInputError(resolve({"joint.law=hybrid", "joint.working_penetration=3 mm"}),
                   "joint.working_penetration");
  ExpectInputError(resolve({"joint.friction=0"}), "joint.friction");
  // An unknown law never gets past the schema.
  Config cfg;
  EXPECT_THROW(cfg.Set("joint.law", "soft"), InputError);
}

// The resolved input written with every run (every key, defaults included, SI numbers) loads
// back as an input and resolves to the same joint, for laws that do and do not take the
// restitution and the damping (overrides at 0 mean "derived").
TEST(ClearanceConfig, ResolvedInputLoadsBackToTheSameJoint) {
  for (const char* law : {"hybrid", "hertz", "kelvin-voigt", "esdu-78035"}) {
    for (const char* friction : {"coulomb", "none"}) {
      SCOPED_TRACE(std::string(law) + " + " + friction);
      const Config cfg =
          Rigid({std::string("joint.law=") + law, std::string("joint.friction_law=") + friction});
      Config back;
      for (const Config::Resolved& r : cfg.Resolve()) back.Set(r.key, r.value);
      const ClearanceJointConfig a = ResolveClearanceJoint(cfg, 1.02);
      const ClearanceJointConfig b = ResolveClearanceJoint(back, 1.02);
      ASSERT_EQ(a.parameters.size(), b.parameters.size());
      for (std::size_t i = 0; i < a.parameters.size(); ++i) {
        EXPECT_EQ(a.parameters[i].name, b.parameters[i].name);
        EXPECT_NEAR(a.parameters[i].value, b.parameters[i].value,
                    1e-9 * std::abs(a.parameters[i].value))
            << a.parameters[i].name;
      }
    }
  }
}

TEST(ClearanceConfig, SliderCrankCarriesTheJointBetweenBushAndJournalAndStartsConsistently) {
  for (const char* preset : {"rigid-rig", "flexible-rig"}) {
    SCOPED_TRACE(preset);
    Config cfg;
    cfg.LoadToml(FindPreset(preset)->toml, preset);
    cfg.Set("joint.type", "clearance");
    cfg.Set("reduction.modes", "2");
    cfg.Set("rod.elements", "8");
    const MechanismModel mm = BuildMechanism(cfg, nullptr);
    ASSERT_GE(mm.clearance.index, 0);
    EXPECT_LT(mm.small_end_joint.index, 0);  // no ideal joint
    EXPECT_FALSE(mm.joint_parameters.empty());
    const multibody::ElementSlot& slot = mm.mechanism.element(mm.clearance);
    EXPECT_EQ(slot.marker_i, mm.small_end.index);
    EXPECT_EQ(slot.marker_j, mm.journal.index);
    EXPECT_EQ(slot.element->type_name(), "clearance-joint");
    // Consistent initial state from p0: the journal sits at the bush centre (open joint).
    multibody::RunData data(mm.mechanism);
    multibody::InitialConditionSpec ic;
    ic.coordinates = mm.p0;
    ic.velocities = Vec::Zero(mm.mechanism.num_coordinates());
    ic.velocities[mm.mechanism.coordinate(mm.crank, multibody::kTheta)] =
        cfg.Quantity("drive.speed");
    const multibody::ConsistentState s =
        multibody::ComputeConsistentState(mm.mechanism, &data, 0.0, ic);
    multibody::SampleView view(mm.mechanism, &data, 0.0, s.y.data(), s.yp.data());
    const multibody::ClearanceResponse r = multibody::CalcClearanceResponse(view, mm.clearance);
    EXPECT_LT(r.kinematics.eccentricity_norm, 1e-12);
    EXPECT_FALSE(r.in_contact);
    EXPECT_LE(view.ConstraintViolation(), 1e-12);

    const MechanismModel twin = BuildMechanism(cfg, mm.rod, /*ideal_joint=*/true);
    EXPECT_LT(twin.clearance.index, 0);
    EXPECT_GE(twin.small_end_joint.index, 0);
    EXPECT_TRUE(twin.joint_parameters.empty());
  }
}

}  // namespace
}  // namespace flexrod
