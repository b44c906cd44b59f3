#include "bouguer/media/library.h"

#include <array>

#include "bouguer/core/csv.h"
#include "bouguer/spectra/spectrum_csv.h"

namespace bouguer::data {
extern const std::string_view red_glass, light_blue_glass, red_wine, white_wine, water, orange_glass, deep_red_glass,
    pale_blue_glass, yellow_glass, cobalt_blue_glass, blue_green_glass, cobalt_chloride, cobalt_nitrate,
    nickel_chloride, copper_sulfate, potassium_dichromate, potassium_chromate, potassium_permanganate, ruby, emerald,
    olive_oil, beer;
}  // namespace bouguer::data

namespace bouguer {
namespace {

struct Entry {
  std::string_view name, description, measured, citation;
  double default_ior;
  const std::string_view* table;
  bool molar = false;
  double min_nm = 360.0, max_nm = 830.0;
  std::string_view extension = {};
};

constexpr std::string_view kHeld = "held at the nearest measured value (the table is constant beyond its ends)";
constexpr std::string_view kAphalo =
    "P. J. Aphalo, photobiologyFilters R package (github.com/aphalo/photobiologyfilters); Aphalo (2015) UV4Plants "
    "Bulletin 2015:1, 21-29";
constexpr std::string_view kAphaloMeasured =
    "total transmittance of one plate, Agilent 8453, 1 nm, 190-1100 nm; surface loss and noise floor removed as "
    "the data file states";
constexpr std::string_view kPhet =
    "PhET Interactive Simulations, University of Colorado Boulder, 'Beer's Law Lab', molar absorptivity measured by "
    "J. Chamberlain (github.com/phetsims/beers-law-lab)";
constexpr std::string_view kPhetMeasured =
    "decadic molar absorptivity of the aqueous solution, L/(mol cm), 1 nm, 380-780 nm (teaching-lab data)";
constexpr std::string_view kGem =
    "Ive (LILYsoft), SpectralRender minerals (spectral_minerals.inc), via syanenko/povgems; public domain";

// Refractive indices at the d line: typical crown/filter glass 1.52; wine (water with about 12 %
// ethanol) 1.343; water 1.333; aqueous salt solutions 1.335; corundum 1.77 (ordinary ray);
// beryl 1.577; olive oil 1.467; beer 1.345.
const std::array<Entry, 22> kEntries = {{
    {"red-glass",
     "Hoya 25A red sharp-cut filter glass (edge near 603 nm); stands in for the paper's red glass with an abrupt "
     "absorption edge",
     "total transmittance of a 2.3 mm multicoated plate, Agilent 8453, 1 nm, 190-1100 nm; surface loss removed by "
     "the 657 nm plateau; readings under 0.3 % (stray light) capped",
     "P. J. Aphalo, photobiologyFilters R package (Hoya-25A-HMC-2.3mm-52mm-ABS.csv); Aphalo (2015) UV4Plants "
     "Bulletin 2015:1, 21-29",
     1.52, &data::red_glass},
    {"light-blue-glass",
     "Heliopan BG38 (Schott BG38-type copper phosphate glass), smooth light blue-green; stands in for the paper's "
     "light blue glass",
     "total transmittance of a 2.3 mm plate, Agilent 8453, 1 nm, 190-1100 nm; surface loss removed by the 504 nm "
     "maximum; readings under 0.05 % (noise floor) capped",
     "P. J. Aphalo, photobiologyFilters R package (Heliopan-BG38-2.3mm-46mm-ABS.CSV); Aphalo (2015) UV4Plants "
     "Bulletin 2015:1, 21-29",
     1.52, &data::light_blue_glass},
    {"red-wine",
     "red wine: FITTED MODEL (no measured wine spectrum exists in the data): red-dye band near 510 nm plus a "
     "yellow-brown exponential, matched to median A420/A520/A620 of 15 commercial muscadine red wines",
     "fitted model; targets A420 1.94, A520 1.90, A620 0.33 per cm (Glories/OIV); band measured 380-780 nm, held "
     "outside",
     "band: PhET Beer's Law Lab drink-mix molar absorptivity (phetsims/beers-law-lab); targets: "
     "maryserviss/commercial_muscadine_wines",
     1.343, &data::red_wine, false, 380.0, 780.0, "fitted model; the dye band is held constant outside 380-780 nm"},
    {"white-wine",
     "white wine: FITTED MODEL (no measured wine spectrum exists in the data): yellow-brown exponential plus a "
     "small red-dye band, matched to median A420/A520/A620 of 11 commercial muscadine white wines",
     "fitted model; targets A420 0.17, A520 0.033, A620 0.006 per cm (Glories/OIV)",
     "band: PhET Beer's Law Lab drink-mix molar absorptivity (phetsims/beers-law-lab); targets: "
     "maryserviss/commercial_muscadine_wines",
     1.343, &data::white_wine, false, 380.0, 780.0, "fitted model; the dye band is held constant outside 380-780 nm"},
    {"water", "pure water (no salt, about 20 degC): nearly clear, blue-green at metres of depth",
     "absorption coefficient a_w, 5 nm, 360-830 nm: IOCCG 2018 consensus of Morel et al. 2007 (360-415 nm), "
     "Pope & Fry 1997 integrating-cavity measurements (420-725 nm) and Kou et al. 1993 (730-830 nm)",
     "IOCCG Protocol Series (2018), Inherent Optical Property Measurements and Protocols: Absorption Coefficient, "
     "Neeley & Mannino (eds.); Pope & Fry, Appl. Opt. 36, 8710 (1997); via raphidoc/aw",
     1.333, &data::water},
    {"orange-glass", "Heliopan 22 orange sharp-cut filter glass (edge near 568 nm), coated", kAphaloMeasured,
     kAphalo, 1.52, &data::orange_glass},
    {"deep-red-glass", "Heliopan filter of Schott RG665 deep-red long-pass glass (edge near 651 nm)", kAphaloMeasured,
     kAphalo, 1.52, &data::deep_red_glass},
    {"pale-blue-glass", "Hoya 82A pale-blue light-balancing glass, multicoated", kAphaloMeasured, kAphalo, 1.52,
     &data::pale_blue_glass},
    {"yellow-glass", "JB450 yellow long-pass glass (Tangsinuo, edge near 460 nm), uncoated", kAphaloMeasured, kAphalo,
     1.52, &data::yellow_glass},
    {"cobalt-blue-glass", "ZB1 cobalt-type violet-blue glass (Tangsinuo): blue pass plus a red leak above 700 nm",
     kAphaloMeasured, kAphalo, 1.52, &data::cobalt_blue_glass},
    {"blue-green-glass", "QB21 copper-type blue-green glass (Tangsinuo), AR coated", kAphaloMeasured, kAphalo, 1.52,
     &data::blue_green_glass},
    {"cobalt-chloride", "cobalt(II) chloride in water (pink); molar", kPhetMeasured, kPhet, 1.335,
     &data::cobalt_chloride, true, 380.0, 780.0, kHeld},
    {"cobalt-nitrate", "cobalt(II) nitrate in water (red-pink); molar", kPhetMeasured, kPhet, 1.335,
     &data::cobalt_nitrate, true, 380.0, 780.0, kHeld},
    {"nickel-chloride", "nickel(II) chloride in water (green); molar", kPhetMeasured, kPhet, 1.335,
     &data::nickel_chloride, true, 380.0, 780.0, kHeld},
    {"copper-sulfate", "copper(II) sulfate in water (blue); molar", kPhetMeasured, kPhet, 1.335, &data::copper_sulfate,
     true, 380.0, 780.0, kHeld},
    {"potassium-dichromate", "potassium dichromate in water (orange); molar", kPhetMeasured, kPhet, 1.335,
     &data::potassium_dichromate, true, 380.0, 780.0, kHeld},
    {"potassium-chromate", "potassium chromate in water (yellow); molar", kPhetMeasured, kPhet, 1.335,
     &data::potassium_chromate, true, 380.0, 780.0, kHeld},
    {"potassium-permanganate", "potassium permanganate in water (purple; PhET's revised 2014 data); molar",
     kPhetMeasured, kPhet, 1.335, &data::potassium_permanganate, true, 380.0, 780.0, kHeld},
    {"ruby", "ruby (Cr-doped corundum): NOT MEASURED - a renderer-authored relative curve scaled to a 5 mm fade distance",
     "relative absorptance S_ABS, 5 nm, 380-730 nm, of undocumented provenance; sigma_a = -ln(1 - S) / 5 mm", kGem,
     1.77, &data::ruby, false, 380.0, 730.0, kHeld},
    {"emerald", "emerald (Cr-doped beryl): NOT MEASURED - a renderer-authored relative curve scaled to a 5 mm fade distance",
     "relative absorptance S_ABS, 20 nm, 380-740 nm, of undocumented provenance; sigma_a = -ln(1 - S) / 5 mm", kGem,
     1.577, &data::emerald, false, 380.0, 740.0, kHeld},
    {"olive-oil", "fresh extra-virgin olive oil (chlorophylls, pheophytins, carotenoids in the oil)",
     "decadic absorbance of the neat oil, 1 nm, 390-720 nm, path taken as 1 cm (not recorded)",
     "S. Jurinovich and V. Domenici, J. Chem. Educ. 99(2), 787-798 (2022), doi:10.1021/acs.jchemed.1c01015 "
     "(sandroj87/EVOODec)",
     1.467, &data::olive_oil, false, 390.0, 720.0, kHeld},
    {"beer", "amber beer of colour SRM 10: FITTED MODEL (mean spectral shape of 99 beers); concentration scales SRM",
     "deLange two-exponential absorbance model, A430 = SRM / 12.7 per cm; valid 380-780 nm",
     "A. J. deLange, 'Color', in Bamforth (ed.), Brewing Materials and Processes, Academic Press 2016, "
     "doi:10.1016/B978-0-12-799954-8.00011-3",
     1.345, &data::beer, false, 380.0, 780.0, "the model's formula extrapolated to 360-380 and 780-830 nm"},
}};

std::vector<LibraryMaterial> load_library() {
  std::vector<LibraryMaterial> out;
  for (const Entry& e : kEntries) {
    const std::string source = "data/materials/" + std::string(e.name) + ".csv";
    out.push_back({e.name, e.description, e.measured, e.citation, e.default_ior,
                   spectrum_from_csv(parse_csv(*e.table, source), 1), e.molar, e.min_nm, e.max_nm, e.extension});
  }
  return out;
}

const std::vector<LibraryMaterial>& library() {
  static const std::vector<LibraryMaterial> materials = load_library();
  return materials;
}

}  // namespace

const LibraryMaterial* find_library_material(std::string_view name) {
  for (const auto& m : library())
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<std::string> library_material_names() {
  std::vector<std::string> names;
  for (const auto& e : kEntries) names.emplace_back(e.name);
  return names;
}

}  // namespace bouguer
