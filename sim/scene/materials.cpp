// The materials an object may name with `material`: a density for objects given neither `mass`
// nor `density`, and a default friction coefficient for the frictional hold (thesis §3.6).
// Densities are typical (nominal) values, rounded; friction coefficients are static, clean and dry,
// material on itself where a table has that pair. They are defaults for an animation tool, not
// design values: a scene that needs a specific value gives `density` or `friction` itself.
#include <array>

#include "sim/scene/scene.hpp"

namespace brisance::scene {

namespace {

// EN 1991-1-1 (Eurocode 1, part 1-1) Annex A gives nominal unit weights in kN/m^3; they are
// quoted here as densities the usual way, 1 kN/m^3 ~ 100 kg/m^3 (24 kN/m^3 concrete -> 2400).
// "Engineering ToolBox" is engineeringtoolbox.com, "Friction and Friction Coefficients for some
// Common Materials" (static, clean and dry) and "Densities of Solids".
constexpr std::array kMaterials = {
    // Common clay brick: about 1900 kg/m^3 solid (Engineering ToolBox "Densities of Solids",
    // brick, common red ~1920 kg/m^3; frogged or perforated bricks are lighter, ~1400-1700).
    // Friction 0.6: Engineering ToolBox lists brick on wood 0.6; it has no brick-on-brick entry,
    // dry brick joints are of the same order. The thesis's wall (§3.6) is tuned by this value.
    Material{"brick", 1900.0, 0.6,
             "density: Engineering ToolBox, Densities of Solids (common red brick); friction: "
             "Engineering ToolBox, Friction Coefficients (brick on wood, 0.6)"},
    // Normal-weight plain concrete 24.0 kN/m^3 (EN 1991-1-1 table A.1) -> ~2400 kg/m^3.
    // Friction 0.6: ACI 318 (e.g. ACI 318-14 table 22.9.4.2) shear-friction coefficient for
    // concrete placed against hardened concrete not intentionally roughened.
    Material{"concrete", 2400.0, 0.6,
             "density: EN 1991-1-1 table A.1 (24 kN/m^3); friction: ACI 318-14 table 22.9.4.2"},
    // Structural steel: rho = 7850 kg/m^3 (EN 1993-1-1 §3.2.6). Friction 0.74: mild steel on mild
    // steel (Engineering ToolBox).
    Material{"steel", 7850.0, 0.74,
             "density: EN 1993-1-1 §3.2.6; friction: Engineering ToolBox (mild steel on mild "
             "steel, 0.74)"},
    // Pine, air-dry: about 350-670 kg/m^3 by species (Engineering ToolBox "Wood Species -
    // Densities"); 500 mid-range. Friction 0.4: wood on wood, clean, 0.25-0.5 (Engineering
    // ToolBox).
    Material{"wood", 500.0, 0.4,
             "density: Engineering ToolBox, Wood Species - Densities (pine); friction: "
             "Engineering ToolBox (wood on wood, 0.25-0.5)"},
    // Soda-lime silicate glass: 2500 kg/m^3 (EN 572-1; EN 1991-1-1 Annex A, "glass in sheets"
    // 25 kN/m^3). Friction 0.9: glass on glass 0.9-1.0 (Engineering ToolBox). Breakable panes
    // (docs/fracture.md): "glass" is annealed float glass, as the thesis's window.
    //  - Young's modulus 70 GPa: EN 572-1 §4 (physical characteristics of soda-lime silicate
    //    glass: E = 7 x 10^10 Pa).
    //  - Fracture toughness K_c = 0.75 MPa m^0.5: Wiederhorn, "Fracture surface energy of
    //    glass", J. Am. Ceram. Soc. 52(2), 99-105 (1969), soda-lime glass. Tempering adds a
    //    surface prestress, not toughness: the same K_c for both.
    //  - Bending strength: annealed 45 MPa, the characteristic bending strength of float glass
    //    (EN 572-1 §4; EN 16612 f_g,k); tempered 120 MPa, the characteristic bending strength of
    //    thermally toughened soda-lime silicate safety glass made of float glass (EN 12150-1).
    //  - Tempered glass's surface compression 75 MPa: its characteristic strength is the float
    //    glass's own plus the temper's prestress (EN 16612 splits f_b,k into f_g,k and the
    //    prestress part f_b,k - f_g,k), 120 - 45 MPa. ASTM C1048 asks at least 69 MPa of fully
    //    tempered glass. It sizes the dice a broken tempered pane falls into (docs/fracture.md).
    Material{"glass", 2500.0, 0.9,
             "density: EN 572-1 (soda-lime silicate glass); friction: Engineering ToolBox (glass "
             "on glass, 0.9-1.0)",
             70e9, 0.75e6, 45e6,
             "annealed float glass: E EN 572-1; K_c Wiederhorn 1969; strength EN 572-1 (45 MPa)"},
    Material{"annealed_glass", 2500.0, 0.9,
             "density: EN 572-1 (soda-lime silicate glass); friction: Engineering ToolBox (glass "
             "on glass, 0.9-1.0)",
             70e9, 0.75e6, 45e6,
             "E: EN 572-1 (70 GPa); K_c: Wiederhorn 1969 (0.75 MPa m^0.5); bending strength: "
             "EN 572-1 / EN 16612 (45 MPa)"},
    Material{"tempered_glass", 2500.0, 0.9,
             "density: EN 572-1 (soda-lime silicate glass); friction: Engineering ToolBox (glass "
             "on glass, 0.9-1.0)",
             70e9, 0.75e6, 120e6,
             "E: EN 572-1 (70 GPa); K_c: Wiederhorn 1969 (0.75 MPa m^0.5); bending strength: "
             "EN 12150-1 (120 MPa); surface compression 75 MPa: EN 12150-1's 120 MPa less "
             "float glass's own 45 MPa (EN 16612's prestress part of the strength)",
             75e6},
    // Aluminium alloys: rho = 2700 kg/m^3 (EN 1999-1-1 §3.2.5). Friction 1.05: aluminium on
    // aluminium 1.05-1.35 (Engineering ToolBox), the lower end.
    Material{"aluminium", 2700.0, 1.05,
             "density: EN 1999-1-1 §3.2.5; friction: Engineering ToolBox (aluminium on "
             "aluminium, 1.05-1.35)"},
    // Granite: 27-30 kN/m^3 (EN 1991-1-1 Annex A, natural stones) -> 2700 kg/m^3, the low end.
    // Friction 0.65: dry
    // granite joints in direct shear tests, about 0.6-0.7 (Vasconcelos, Lourenço & Oliveira,
    // "Experimental shear behaviour of stone masonry joints", SAHC 2008).
    Material{"granite", 2700.0, 0.65,
             "density: EN 1991-1-1 Annex A (granite 27-30 kN/m^3); friction: Vasconcelos, "
             "Lourenco & Oliveira 2008 (dry granite joints)"},
    // "stone": the same values as granite, for scenes that do not care which stone.
    Material{"stone", 2700.0, 0.65, "as granite"},
};

}  // namespace

std::vector<Material> known_materials() {
  return {kMaterials.begin(), kMaterials.end()};
}

}  // namespace brisance::scene
