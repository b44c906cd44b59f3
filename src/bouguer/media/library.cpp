#include "bouguer/media/library.h"

#include <array>

#include "bouguer/io/csv.h"
#include "bouguer/io/spectrum_csv.h"

namespace bouguer::data {
extern const std::string_view red_glass, light_blue_glass, red_wine, white_wine, water;
}  // namespace bouguer::data

namespace bouguer {
namespace {

struct Entry {
  std::string_view name, description, measured, citation;
  double default_ior;
  const std::string_view* table;
};

// Refractive indices: typical crown/filter glass 1.52; wine (water with about 12 % ethanol) 1.343;
// water 1.333.
const std::array<Entry, 5> kEntries = {{
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
     1.343, &data::red_wine},
    {"white-wine",
     "white wine: FITTED MODEL (no measured wine spectrum exists in the data): yellow-brown exponential plus a "
     "small red-dye band, matched to median A420/A520/A620 of 11 commercial muscadine white wines",
     "fitted model; targets A420 0.17, A520 0.033, A620 0.006 per cm (Glories/OIV)",
     "band: PhET Beer's Law Lab drink-mix molar absorptivity (phetsims/beers-law-lab); targets: "
     "maryserviss/commercial_muscadine_wines",
     1.343, &data::white_wine},
    {"water", "pure water (no salt, about 20 degC): nearly clear, blue-green at metres of depth",
     "absorption coefficient a_w, 5 nm, 360-830 nm: IOCCG 2018 consensus of Morel et al. 2007 (360-415 nm), "
     "Pope & Fry 1997 integrating-cavity measurements (420-725 nm) and Kou et al. 1993 (730-830 nm)",
     "IOCCG Protocol Series (2018), Inherent Optical Property Measurements and Protocols: Absorption Coefficient, "
     "Neeley & Mannino (eds.); Pope & Fry, Appl. Opt. 36, 8710 (1997); via raphidoc/aw",
     1.333, &data::water},
}};

std::vector<LibraryMaterial> load_library() {
  std::vector<LibraryMaterial> out;
  for (const Entry& e : kEntries) {
    const std::string source = "data/materials/" + std::string(e.name) + ".csv";
    out.push_back({e.name, e.description, e.measured, e.citation, e.default_ior,
                   spectrum_from_csv(parse_csv(*e.table, source), 1)});
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
