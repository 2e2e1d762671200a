#include "config.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <toml++/toml.hpp>

namespace softflow {
namespace {

// Reads the keys of one table, remembering which ones were asked for so that
// anything left over is reported as unknown.
class TableReader {
 public:
  TableReader(const toml::table& root, std::string name) : name_(std::move(name)) {
    if (auto* n = root.get(name_)) {
      if (!n->is_table()) throw InputError("'" + name_ + "' must be a table ([" + name_ + "])");
      table_ = n->as_table();
    }
  }

  bool present() const { return table_ != nullptr; }
  bool is_string(const char* key) const {
    const toml::node* n = table_ ? table_->get(key) : nullptr;
    return n && n->is_string();
  }

  template <class T>
  bool read(const char* key, T& out, bool required) {
    seen_.insert(key);
    const toml::node* n = table_ ? table_->get(key) : nullptr;
    if (!n) {
      if (required) throw InputError("missing key '" + full(key) + "'");
      return false;
    }
    if constexpr (std::is_same_v<T, std::string>) {
      if (!n->is_string()) throw InputError("'" + full(key) + "' must be a string");
      out = n->as_string()->get();
    } else if constexpr (std::is_same_v<T, bool>) {
      if (!n->is_boolean()) throw InputError("'" + full(key) + "' must be true or false");
      out = n->as_boolean()->get();
    } else if constexpr (std::is_integral_v<T>) {
      if (!n->is_integer()) throw InputError("'" + full(key) + "' must be an integer");
      out = static_cast<T>(n->as_integer()->get());
    } else {
      if (n->is_integer())
        out = static_cast<T>(n->as_integer()->get());
      else if (n->is_floating_point())
        out = static_cast<T>(n->as_floating_point()->get());
      else
        throw InputError("'" + full(key) + "' must be a number");
      if (!std::isfinite(double(out))) throw InputError("'" + full(key) + "' must be finite");
    }
    return true;
  }

  // a fixed-length array of numbers
  bool read_numbers(const char* key, Real* out, int n, bool required) {
    seen_.insert(key);
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    if (!node) {
      if (required) throw InputError("missing key '" + full(key) + "'");
      return false;
    }
    const toml::array* a = node->as_array();
    if (!a || int(a->size()) != n)
      throw InputError("'" + full(key) + "' must be an array of " + std::to_string(n) + " numbers");
    for (int m = 0; m < n; ++m) {
      const toml::node& e = *a->get(m);
      if (e.is_integer())
        out[m] = Real(e.as_integer()->get());
      else if (e.is_floating_point())
        out[m] = Real(e.as_floating_point()->get());
      else
        throw InputError("'" + full(key) + "' must be an array of " + std::to_string(n) + " numbers");
      if (!std::isfinite(double(out[m]))) throw InputError("'" + full(key) + "' must be finite");
    }
    return true;
  }

  template <class T>
  void positive(const char* key, T v) const {
    if (!(v > 0)) throw InputError("'" + full(key) + "' must be positive (got " + str(v) + ")");
  }
  template <class T>
  void non_negative(const char* key, T v) const {
    if (v < 0) throw InputError("'" + full(key) + "' must not be negative (got " + str(v) + ")");
  }

  void finish() const {
    if (!table_) return;
    for (auto&& [k, v] : *table_) {
      if (!seen_.count(std::string(k.str())))
        throw InputError("unknown key '" + full(std::string(k.str())) + "'");
    }
  }

  std::string full(const std::string& key) const { return name_ + "." + key; }

 private:
  template <class T>
  static std::string str(T v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  std::string name_;
  const toml::table* table_ = nullptr;
  std::set<std::string> seen_;
};

// "grid.nx=64" -> sets root["grid"]["nx"] = 64 (value parsed as TOML; a bare
// word that is not valid TOML is taken as a string).
void apply_override(toml::table& root, const std::string& text) {
  auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("override '" + text + "' is not of the form table.key=value");
  std::string path = text.substr(0, eq), value = text.substr(eq + 1);
  auto dot = path.find('.');
  if (dot == std::string::npos || path.find('.', dot + 1) != std::string::npos)
    throw InputError("override '" + text + "': the key must be table.key (one dot)");
  std::string table = path.substr(0, dot), key = path.substr(dot + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"v", value}};
  }
  if (!root.contains(table)) root.insert(table, toml::table{});
  auto* t = root.get(table)->as_table();
  if (!t) throw InputError("override '" + text + "': '" + table + "' is not a table");
  t->insert_or_assign(key, *parsed.get("v"));
}

Real det_of(const Real* b) {
  return b[0] * (b[3] * b[5] - b[4] * b[4]) - b[1] * (b[1] * b[5] - b[4] * b[2]) +
         b[2] * (b[1] * b[4] - b[3] * b[2]);
}

// B must be a deformation's: symmetric positive definite (all leading minors
// positive), and near det 1 (a scaling beyond round-off is a wrong input, not
// a rounded one)
void check_initial_b(const Real* b) {
  const Real m2 = b[0] * b[3] - b[1] * b[1], d = det_of(b);
  if (!(b[0] > 0 && m2 > 0 && d > 0))
    throw InputError("'particles.initial_b' = [xx, xy, xz, yy, yz, zz] must be positive definite");
  if (std::abs(d - 1) > 1e-3)
    throw InputError(
        "'particles.initial_b' must have det B = 1 within 1e-3 (an incompressible solid's; got " +
        std::to_string(d) + ")");
}

}  // namespace

Real Config::end_time_resolved() const {
  if (time.end_time >= 0) return time.end_time;
  return time.end_strain / shear_rate();
}

Config parse_config(const std::string& text, const std::string& name,
                    const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << name << ": invalid TOML at line " << e.source().begin.line << ": " << e.description();
    throw InputError(s.str());
  }
  for (const auto& o : overrides) apply_override(root, o);

  const std::set<std::string> tables = {"grid",   "fluid",    "walls",     "time",   "initial",
                                        "output", "parallel", "particles", "restart"};
  for (auto&& [k, v] : root) {
    if (!tables.count(std::string(k.str())))
      throw InputError("unknown key '" + std::string(k.str()) +
                       "' (tables: grid, fluid, walls, "
                       "time, initial, output, parallel, particles, restart)");
  }

  Config c;
  c.case_name = name;
  {
    TableReader r(root, "grid");
    r.read("nx", c.grid.nx, true);
    r.read("ny", c.grid.ny, true);
    r.read("nz", c.grid.nz, true);
    r.read("lx", c.grid.lx, true);
    r.read("ly", c.grid.ly, true);
    r.read("lz", c.grid.lz, true);
    r.positive("nx", c.grid.nx);
    r.positive("ny", c.grid.ny);
    r.positive("nz", c.grid.nz);
    r.positive("lx", c.grid.lx);
    r.positive("ly", c.grid.ly);
    r.positive("lz", c.grid.lz);
    r.finish();
  }
  {
    TableReader r(root, "fluid");
    r.read("rho", c.fluid.rho, true);
    r.read("mu", c.fluid.mu, true);
    r.positive("rho", c.fluid.rho);
    r.positive("mu", c.fluid.mu);
    r.finish();
  }
  {
    TableReader r(root, "walls");
    r.read("velocity", c.walls.velocity, true);
    r.read("omega", c.walls.omega, false);
    r.non_negative("omega", c.walls.omega);
    r.finish();
  }
  {
    TableReader r(root, "time");
    bool has_strain = r.read("end_strain", c.time.end_strain, false);
    bool has_time = r.read("end_time", c.time.end_time, false);
    if (has_strain == has_time) throw InputError("give exactly one of 'time.end_strain' and 'time.end_time'");
    if (has_strain) {
      r.non_negative("end_strain", c.time.end_strain);
      if (c.walls.velocity == 0)
        throw InputError("'time.end_strain' needs a non-zero 'walls.velocity'; use 'time.end_time'");
    }
    if (has_time) r.non_negative("end_time", c.time.end_time);
    r.read("cfl", c.time.cfl, false);
    r.read("dt_max", c.time.dt_max, false);
    r.read("max_steps", c.time.max_steps, false);
    r.read("viscous", c.time.viscous, false);
    if (c.time.viscous != "explicit" && c.time.viscous != "implicit")
      throw InputError("'time.viscous' must be \"explicit\" or \"implicit\" (got \"" + c.time.viscous +
                       "\")");
    r.positive("cfl", c.time.cfl);
    if (c.time.cfl > 1) throw InputError("'time.cfl' must be at most 1 (it scales the stability limits)");
    r.positive("dt_max", c.time.dt_max);
    r.non_negative("max_steps", c.time.max_steps);
    r.finish();
  }
  {
    TableReader r(root, "initial");
    r.read("type", c.initial.type, false);
    r.read("amplitude", c.initial.amplitude, false);
    r.read("omega", c.initial.omega, false);
    if (c.initial.type != "rest" && c.initial.type != "couette" && c.initial.type != "manufactured")
      throw InputError("'initial.type' must be \"rest\", \"couette\" or \"manufactured\" (got \"" +
                       c.initial.type + "\")");
    r.finish();
  }
  {
    TableReader r(root, "output");
    r.read("dir", c.output.dir, false);
    r.read("progress_every", c.output.progress_every, false);
    r.read("series_every", c.output.series_every, false);
    r.read("fields_every", c.output.fields_every, false);
    r.read("checkpoint_every", c.output.checkpoint_every, false);
    r.read("checkpoint_minutes", c.output.checkpoint_minutes, false);
    r.read("profiles_every", c.output.profiles_every, false);
    r.read("average_from_strain", c.output.average_from_strain, false);
    if (c.output.dir.empty()) throw InputError("'output.dir' must not be empty");
    r.non_negative("progress_every", c.output.progress_every);
    r.non_negative("series_every", c.output.series_every);
    r.non_negative("fields_every", c.output.fields_every);
    r.non_negative("checkpoint_every", c.output.checkpoint_every);
    r.non_negative("checkpoint_minutes", c.output.checkpoint_minutes);
    r.non_negative("profiles_every", c.output.profiles_every);
    r.finish();
  }
  {
    TableReader r(root, "parallel");
    r.read("px", c.parallel.px, false);
    r.read("pz", c.parallel.pz, false);
    r.non_negative("px", c.parallel.px);
    r.non_negative("pz", c.parallel.pz);
    r.finish();
  }
  {
    TableReader r(root, "particles");
    ParticleConfig& p = c.particles;
    p.enabled = r.present();
    if (p.enabled) {
      r.read("shape", p.shape, false);
      if (p.shape != "spheres" && p.shape != "layer")
        throw InputError("'particles.shape' must be \"spheres\" or \"layer\" (got \"" + p.shape + "\")");
      if (p.shape == "spheres") {
        r.read("radius", p.radius, true);
        r.positive("radius", p.radius);
        bool has_phi = r.read("volume_fraction", p.volume_fraction, false);
        bool has_n = r.read("count", p.count, false);
        if (has_phi == has_n)
          throw InputError("give exactly one of 'particles.volume_fraction' and 'particles.count'");
        if (has_phi && !(p.volume_fraction > 0 && p.volume_fraction < 0.6))
          throw InputError("'particles.volume_fraction' must be in (0, 0.6) (got " +
                           std::to_string(p.volume_fraction) + ")");
        if (has_n) r.positive("count", p.count);
        r.read("placement", p.placement, false);
        if (p.placement != "stratified" && p.placement != "random" && p.placement != "centre")
          throw InputError("'particles.placement' must be \"stratified\", \"random\" or \"centre\" (got \"" +
                           p.placement + "\")");
        // one sphere, given as count = 1 or by a volume fraction of one sphere in the box
        const double one =
            4.0 / 3.0 * M_PI * p.radius * p.radius * p.radius / (c.grid.lx * c.grid.ly * c.grid.lz);
        if (p.placement == "centre" && !(has_n ? p.count == 1 : std::lround(p.volume_fraction / one) == 1))
          throw InputError(
              "'particles.placement = \"centre\"' needs one sphere ('particles.count = 1', or a "
              "volume fraction that rounds to one sphere)");
        r.read("min_gap", p.min_gap, false);
        r.non_negative("min_gap", p.min_gap);
        r.read("min_gap_cells", p.min_gap_cells, false);
        r.non_negative("min_gap_cells", p.min_gap_cells);
        long seed = 1;
        r.read("seed", seed, false);
        r.non_negative("seed", seed);
        p.seed = (unsigned long)seed;
        r.read("subsamples", p.subsamples, false);
        r.positive("subsamples", p.subsamples);
        if (2 * (p.radius + p.min_gap) > c.grid.ly)
          throw InputError("particles of radius " + std::to_string(p.radius) + " and gap " +
                           std::to_string(p.min_gap) +
                           " do not fit between the walls (ly = " + std::to_string(c.grid.ly) + ")");
      } else {
        r.read("layer_thickness", p.layer_thickness, true);
        r.positive("layer_thickness", p.layer_thickness);
        if (p.layer_thickness >= c.grid.ly)
          throw InputError("'particles.layer_thickness' must be smaller than 'grid.ly'");
      }
      bool has_ca = r.read("capillary", p.capillary, false);
      bool has_g = r.read("shear_modulus", p.shear_modulus, false);
      if (has_ca == has_g)
        throw InputError("give exactly one of 'particles.capillary' and 'particles.shear_modulus'");
      if (has_ca) {
        r.positive("capillary", p.capillary);
        if (c.walls.velocity == 0)
          throw InputError(
              "'particles.capillary' needs a non-zero 'walls.velocity' (Ca = mu_f gamma / G); "
              "give 'particles.shear_modulus' instead");
      }
      if (has_g) r.positive("shear_modulus", p.shear_modulus);
      r.read("viscosity_ratio", p.viscosity_ratio, false);
      r.positive("viscosity_ratio", p.viscosity_ratio);
      r.read("phi_scheme", p.phi_scheme, false);
      if (p.phi_scheme != "thinc" && p.phi_scheme != "mthinc" && p.phi_scheme != "weno5")
        throw InputError("'particles.phi_scheme' must be \"thinc\", \"mthinc\" or \"weno5\" (got \"" +
                         p.phi_scheme + "\")");
      r.read("thinc_beta", p.thinc_beta, false);
      if (!(p.thinc_beta >= 0.5 && p.thinc_beta <= 10))
        throw InputError("'particles.thinc_beta' must be in [0.5, 10] (got " + std::to_string(p.thinc_beta) +
                         ")");
      r.read("b_extension", p.b_extension, false);
      r.read("b_solid_phi", p.b_solid_phi, false);
      if (!(p.b_solid_phi >= 0.2 && p.b_solid_phi <= 0.99))
        throw InputError("'particles.b_solid_phi' must be in [0.2, 0.99] (got " +
                         std::to_string(p.b_solid_phi) + ")");
      r.read("debris_return", p.debris_return, false);
      if (p.debris_return && !p.b_extension)
        throw InputError(
            "'particles.debris_return' needs 'particles.b_extension' (it runs with B's extension)");
      r.read("b_extension_stages", p.b_extension_stages, false);
      if (p.b_extension_stages != "last" && p.b_extension_stages != "all")
        throw InputError("'particles.b_extension_stages' must be \"last\" or \"all\" (got \"" +
                         p.b_extension_stages + "\")");
      r.read("unimodular_b", p.unimodular_b, false);
      r.read("b_fallback", p.b_fallback, false);
      r.read("b_fallback_det", p.b_fallback_det, false);
      if (!(p.b_fallback_det >= 0 && p.b_fallback_det < 1))
        throw InputError("'particles.b_fallback_det' must be in [0, 1) (got " +
                         std::to_string(p.b_fallback_det) + ")");
      if (r.is_string("colour_fields")) {
        std::string v;
        r.read("colour_fields", v, false);
        if (v != "auto")
          throw InputError("'particles.colour_fields' must be an integer >= 0 or \"auto\" (got \"" + v +
                           "\")");
        p.colour_fields = ParticleConfig::auto_colours;
      } else if (r.read("colour_fields", p.colour_fields, false)) {
        r.non_negative("colour_fields", p.colour_fields);
      }
      if (p.colour_fields > 0 && p.shape != "spheres")
        throw InputError("'particles.colour_fields' needs 'particles.shape = \"spheres\"'");
      r.read("colour_cut", p.colour_cut, false);
      // below phi's own cut the tails would outlive phi's; above 1e-3 the cut
      // would reach into the interface MTHINC reconstructs
      if (!(p.colour_cut >= 1e-10 && p.colour_cut <= 1e-3)) {
        std::ostringstream got;
        got << p.colour_cut;  // 1e-12, not to_string's 0.000000
        throw InputError("'particles.colour_cut' must be in [1e-10, 1e-3] (got " + got.str() + ")");
      }
      r.read("colour_sum_bound", p.colour_sum_bound, false);
      r.read("solid_model", p.solid_model, false);
      if (p.solid_model != "phi_b" && p.solid_model != "reference_map")
        throw InputError("'particles.solid_model' must be \"phi_b\" or \"reference_map\" (got \"" +
                         p.solid_model + "\")");
      if (p.debris_return && p.solid_model != "phi_b")
        throw InputError(
            "'particles.debris_return' needs 'particles.solid_model = \"phi_b\"' (the map makes phi)");
      r.read("map_volume_correction", p.map_volume_correction, false);
      if (p.map_volume_correction && p.solid_model != "reference_map")
        throw InputError(
            "'particles.map_volume_correction' needs 'particles.solid_model = \"reference_map\"'");
      if (r.read("map_correction_passes", p.map_correction_passes, false)) {
        if (!p.map_volume_correction)
          throw InputError(
              "'particles.map_correction_passes' needs 'particles.map_volume_correction = true'");
        if (p.map_correction_passes < 1 || p.map_correction_passes > 8)
          throw InputError("'particles.map_correction_passes' must be in [1, 8] (got " +
                           std::to_string(p.map_correction_passes) + ")");
      }
      if (r.read_numbers("initial_b", p.initial_b, 6, false)) {
        if (p.shape != "spheres")
          throw InputError("'particles.initial_b' needs 'particles.shape = \"spheres\"'");
        check_initial_b(p.initial_b);
        // the incompressible solid's B has det 1: scale a rounded input onto it
        const Real* b = p.initial_b;
        const Real s = std::cbrt(det_of(b));
        for (int m = 0; m < 6; ++m) p.initial_b[m] /= s;
        if (2 * (p.radius * std::sqrt(p.initial_b[3]) + p.min_gap) > c.grid.ly)
          throw InputError("particles of radius " + std::to_string(p.radius) +
                           " deformed by 'particles.initial_b' (" +
                           std::to_string(std::sqrt(p.initial_b[3])) + " r across y) and gap " +
                           std::to_string(p.min_gap) +
                           " do not fit between the walls (ly = " + std::to_string(c.grid.ly) + ")");
        if (2 * p.radius * std::sqrt(p.initial_b[0]) >= c.grid.lx ||
            2 * p.radius * std::sqrt(p.initial_b[5]) >= c.grid.lz)
          throw InputError(
              "a particle deformed by 'particles.initial_b' is wider than the periodic box in x or z");
      }
      if (p.solid_model == "reference_map") {
        const bool one_sphere = p.shape == "spheres" && (p.count == 1 || p.placement == "centre");
        if (!one_sphere || p.colour_fields > 0 || p.deformed_start())
          throw InputError(
              "'particles.solid_model = \"reference_map\"' is written for one undeformed sphere "
              "('particles.count = 1' or 'placement = \"centre\"', no 'colour_fields', no 'initial_b')");
      }
    }
    r.finish();
  }
  {
    TableReader r(root, "restart");
    r.read("file", c.restart, false);
    r.finish();
  }
  std::ostringstream resolved;
  resolved << root;
  c.source_text = resolved.str();
  return c;
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open case file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), std::filesystem::path(path).stem().string(), overrides);
}

namespace {
std::string divide_error(const char* what, int n, const char* by, int p, const char* why) {
  return std::string("grid.") + what + " = " + std::to_string(n) + " is not divisible by " + by + " = " +
         std::to_string(p) + " (" + why + ")";
}
}  // namespace

void resolve_rank_grid(Config& c, int nranks) {
  int& px = c.parallel.px;
  int& pz = c.parallel.pz;
  if (px == 0 && pz == 0) {
    // the most square factorization whose factors divide the grid
    int best = -1;
    for (int a = 1; a <= nranks; ++a) {
      if (nranks % a) continue;
      int b = nranks / a;
      bool ok = c.grid.nx % a == 0 && c.grid.nz % b == 0 && c.grid.ny % a == 0 && c.grid.ny % b == 0 &&
                c.grid.nx / a >= 3 && c.grid.nz / b >= 3;
      if (ok && (best < 0 || std::abs(a - b) < std::abs(best - nranks / best))) best = a;
    }
    if (best < 0)
      throw InputError("no rank grid px x pz = " + std::to_string(nranks) + " divides the grid " +
                       std::to_string(c.grid.nx) + " x " + std::to_string(c.grid.ny) + " x " +
                       std::to_string(c.grid.nz) + " (px must divide nx and ny, pz must divide nz and ny)");
    px = best;
    pz = nranks / best;
  } else if (px == 0 || pz == 0) {
    int given = px ? px : pz;
    if (nranks % given)
      throw InputError("parallel." + std::string(px ? "px" : "pz") + " = " + std::to_string(given) +
                       " does not divide the " + std::to_string(nranks) + " MPI ranks");
    (px ? pz : px) = nranks / given;
  }
  if (px * pz != nranks)
    throw InputError("parallel.px * parallel.pz = " + std::to_string(px * pz) + " but the run has " +
                     std::to_string(nranks) + " MPI ranks");
  if (c.grid.nx % px)
    throw InputError(divide_error("nx", c.grid.nx, "parallel.px", px, "x is split among px ranks"));
  if (c.grid.nz % pz)
    throw InputError(divide_error("nz", c.grid.nz, "parallel.pz", pz, "z is split among pz ranks"));
  if (c.grid.ny % px)
    throw InputError(
        divide_error("ny", c.grid.ny, "parallel.px", px, "the FFT in x splits y among px ranks"));
  if (c.grid.ny % pz)
    throw InputError(
        divide_error("ny", c.grid.ny, "parallel.pz", pz, "the FFT in z splits y among pz ranks"));
  // a rank's block must be at least as wide as the ghost layers it sends
  if (c.grid.nx / px < 3)
    throw InputError("grid.nx / parallel.px = " + std::to_string(c.grid.nx / px) +
                     " cells per rank in x; at least 3 are needed (the ghost width)");
  if (c.grid.nz / pz < 3)
    throw InputError("grid.nz / parallel.pz = " + std::to_string(c.grid.nz / pz) +
                     " cells per rank in z; at least 3 are needed (the ghost width)");
  if (c.grid.ny < 4) throw InputError("grid.ny must be at least 4 (got " + std::to_string(c.grid.ny) + ")");
}

}  // namespace softflow
