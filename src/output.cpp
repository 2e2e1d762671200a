#include "output.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;

namespace softflow {

void check_output_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError("output folder '" + dir + "' cannot be created: " + ec.message());
  const std::string probe = dir + "/.softflow-write-test";
  std::ofstream f(probe);
  if (!f || !(f << "x") || (f.close(), false))
    throw InputError("output folder '" + dir + "' is not writable");
  fs::remove(probe, ec);
}

namespace {
std::string series_header(bool solid) {
  std::string h = "step,time,strain,dt,kinetic_energy,max_div,max_speed,tau_bottom,tau_top,mu_eff,n1,n2";
  for (int b = 0; b < n_budget; ++b) h += std::string(",") + budget_name(b);
  if (solid)
    h += ",solid_volume,phi_min,phi_max,detb_min,detb_max,detb_raw_min,detb_raw_max,unimodular_removed,"
         "elastic_share_lowphi,b_fallback_cells,solid_share_lowphi,n1_elastic,map_det_corrected,map_volume_"
         "moved,debris_returned";
  return h;
}
const char* particles_header =
    "step,time,strain,count,taylor_mean,taylor_std,a_xy_mean,b_xy_mean,a_mean,b_mean,c_mean,angle_mean_deg,"
    "phi_e,"
    "axes_scale_mean,taylor_b_mean,angle_b_mean_deg";
std::string profiles_header() {
  std::string h = "step,strain,row,y_centre,u_mean,phi_mean,y_face";
  for (int b = 0; b < n_budget; ++b) h += std::string(",") + budget_name(b);
  return h;
}

std::string snapshot_name(long step) {
  std::ostringstream s;
  s << "fields_" << std::setw(8) << std::setfill('0') << step << ".h5";
  return s.str();
}
}  // namespace

Output::Output(FlowSolver& s, bool restarted)
    : s_(s), dir_(s.config().output.dir), file_(s.decomposition(), s.grid()) {
  const bool root = s.decomposition().is_root();
  // after a restart keep what the interrupted run wrote up to the checkpoint's step
  const long keep = restarted ? s.step : -1;
  series_ = CsvSeries(root, dir_ + "/series.csv", series_header(s.solid() != nullptr), keep);
  if (s.solid()) particles_ = CsvSeries(root, dir_ + "/particles.csv", particles_header, keep);
  if (s.config().output.profiles_every)
    profiles_ = CsvSeries(root, dir_ + "/profiles_series.csv", profiles_header(), keep);
  if (!root) return;
  if (!restarted) return;
  std::regex pat(R"(fields_(\d{8})\.h5)");
  for (const auto& e : fs::directory_iterator(dir_)) {
    std::smatch m;
    std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, pat)) continue;
    long st = std::stol(m[1]);
    if (st > s.step) continue;
    hid_t f = H5Fopen(e.path().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) continue;
    double t = 0;
    if (H5Aexists(f, "time") > 0) {
      hid_t a = H5Aopen(f, "time", H5P_DEFAULT);
      H5Aread(a, H5T_NATIVE_DOUBLE, &t);
      H5Aclose(a);
    }
    H5Fclose(f);
    snapshots_.push_back({st, t});
  }
  std::sort(snapshots_.begin(), snapshots_.end());
}

void Output::write_text(const std::string& name, const std::string& text) {
  if (!s_.decomposition().is_root()) return;
  const std::string path = dir_ + "/" + name, tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f) throw std::runtime_error("cannot write '" + tmp + "'");
  }
  fs::rename(tmp, path);
}

void Output::series_row(const FlowScalars& f, Real dt) {
  std::ostringstream r;
  r << std::setprecision(10) << s_.step << "," << s_.time << "," << s_.time * s_.config().shear_rate() << ","
    << dt << "," << f.kinetic_energy << "," << f.max_div << "," << f.max_speed << "," << f.tau_bottom << ","
    << f.tau_top << "," << f.mu_eff << "," << f.n1 << "," << f.n2 << "," << f.fluid_viscous << ","
    << f.particle_viscous << "," << f.particle_elastic << "," << f.fluid_reynolds << ","
    << f.particle_reynolds;
  if (s_.solid())
    r << "," << std::setprecision(17) << f.solid_volume << std::setprecision(10) << "," << f.phi_min << ","
      << f.phi_max << "," << f.detb_min << "," << f.detb_max << "," << f.detb_raw_min << "," << f.detb_raw_max
      << "," << f.unimodular_removed << "," << f.elastic_share_lowphi << "," << f.b_fallback_cells << ","
      << f.solid_share_lowphi << "," << f.n1_elastic << "," << f.map_det_corrected << ","
      << f.map_volume_moved << "," << f.debris_returned;
  series_.append(r.str());
}

void Output::particles_row(const std::vector<ParticleShape>& shapes) {
  const Grid& g = s_.grid();
  double n = double(shapes.size()), t = 0, t2 = 0, axy = 0, bxy = 0, a = 0, b = 0, c = 0, ang = 0, b3 = 0,
         sc = 0, tb = 0, angb = 0;
  for (const auto& p : shapes) {
    t += p.taylor, t2 += p.taylor * p.taylor, axy += p.a_xy, bxy += p.b_xy, sc += p.axes_scale;
    tb += p.taylor_b, angb += p.angle_b;
    a += p.a, b += p.b, c += p.c, ang += p.angle, b3 += p.b_xy * p.b_xy * p.b_xy;
  }
  const double m = std::max(n, 1.0);
  const double tm = t / m, ts = std::sqrt(std::max(0.0, t2 / m - tm * tm));
  // Phi_e = N (4/3) pi b^3 / V_box, b the semi-minor axis of the x-y section
  const double phi_e = 4.0 / 3.0 * M_PI * b3 / (g.lx * g.ly * g.lz);
  std::ostringstream r;
  r << std::setprecision(10) << s_.step << "," << s_.time << "," << s_.time * s_.config().shear_rate() << ","
    << shapes.size() << "," << tm << "," << ts << "," << axy / m << "," << bxy / m << "," << a / m << ","
    << b / m << "," << c / m << "," << ang / m * 180 / M_PI << "," << phi_e << "," << sc / m << "," << tb / m
    << "," << angb / m * 180 / M_PI;
  particles_.append(r.str());
}

void Output::profile_sample(const FlowProfiles& p) {
  if (!s_.decomposition().is_root()) return;
  std::ostringstream r;
  r << std::setprecision(10);
  const double strain = s_.time * s_.config().shear_rate();
  for (size_t j = 0; j < p.y_face.size(); ++j) {
    r.str("");
    r << s_.step << "," << strain << "," << j << ",";
    if (j < p.y_centre.size())
      r << p.y_centre[j] << "," << p.u_mean[j] << "," << p.phi_mean[j] << ",";
    else
      r << ",,,";
    r << p.y_face[j];
    for (int b = 0; b < n_budget; ++b) r << "," << p.budget[b][j];
    profiles_.append(r.str());
  }
}

namespace {
// the solid fields by name, for snapshots and checkpoints
void add_solid(std::vector<H5Item>& items, const FlowSolver& s) {
  if (!s.solid()) return;
  const char* names[n_solid_fields] = {"phi", "Bxx", "Bxy", "Bxz", "Byy", "Byz", "Bzz"};
  for (int m = 0; m < n_solid_fields; ++m) items.push_back({names[m], s.solid()->fields().q[m]});
  const ColourFields& c = s.solid()->colours();
  for (int m = 0; m < c.size(); ++m) items.push_back({"colour_" + std::to_string(m), c.colour(m)});
  const ReferenceMap& map = s.solid()->reference_map();
  if (map.on()) {
    for (int m = 0; m < 3; ++m) items.push_back({std::string("xi_") + "xyz"[m], map.xi(m)});
    items.push_back({"xi_inside", map.inside()});
  }
}
}  // namespace

void Output::snapshot() {
  auto& st = s_.state();
  const std::string name = snapshot_name(s_.step);
  const std::string path = dir_ + "/" + name;
  std::vector<H5Item> items = {{"u", st.u, Sample::x_face_to_centre},
                               {"v", st.v, Sample::y_face_to_centre},
                               {"w", st.w, Sample::z_face_to_centre},
                               {"p", st.p, Sample::raw}};
  add_solid(items, s_);
  file_.write(path + ".tmp", items, {{"time", s_.time}, {"step", double(s_.step)}});
  commit_file(s_.decomposition(), path + ".tmp", path);
  if (snapshots_.empty() || snapshots_.back().first != s_.step) snapshots_.push_back({s_.step, s_.time});
  write_xdmf();
}

// XDMF 3 with the cell centres as the nodes of a co-rectilinear mesh.
void Output::write_xdmf() {
  const Grid& g = s_.grid();
  std::ostringstream x;
  x << std::setprecision(15);
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"softflow\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const std::string dims = std::to_string(g.nz) + " " + std::to_string(g.ny) + " " + std::to_string(g.nx);
  for (const auto& [step, time] : snapshots_) {
    const std::string file = snapshot_name(step);
    x << "<Grid Name=\"step " << step << "\" GridType=\"Uniform\">\n"
      << "<Time Value=\"" << time << "\"/>\n"
      << "<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << dims << "\"/>\n"
      << "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
      << "<DataItem Dimensions=\"3\" Format=\"XML\">" << g.dz / 2 << " " << -g.h() + g.dy / 2 << " "
      << g.dx / 2 << "</DataItem>\n"
      << "<DataItem Dimensions=\"3\" Format=\"XML\">" << g.dz << " " << g.dy << " " << g.dx
      << "</DataItem>\n</Geometry>\n";
    std::vector<const char*> scalars = {"u", "v", "w", "p"};
    if (s_.solid())
      for (const char* f : {"phi", "Bxx", "Bxy", "Bxz", "Byy", "Byz", "Bzz"}) scalars.push_back(f);
    for (const char* f : scalars) {
      x << "<Attribute Name=\"" << f << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        << "<DataItem Dimensions=\"" << dims << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
        << file << ":/" << f << "</DataItem>\n</Attribute>\n";
    }
    x << "<Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
      << "<DataItem ItemType=\"Function\" Function=\"JOIN($0, $1, $2)\" Dimensions=\"" << dims << " 3\">\n";
    for (const char* f : {"u", "v", "w"})
      x << "<DataItem Dimensions=\"" << dims << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
        << file << ":/" << f << "</DataItem>\n";
    x << "</DataItem>\n</Attribute>\n</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  write_text("fields.xdmf", x.str());
}

void Output::checkpoint(const std::vector<ParticleShape>& particles) {
  auto& st = s_.state();
  const std::string path = dir_ + "/checkpoint.h5";
  const Grid& g = s_.grid();
  std::vector<H5Item> items = {{"u", st.u}, {"v", st.v}, {"w", st.w}, {"p", st.p}};
  add_solid(items, s_);
  std::vector<double> centroids, reach;
  for (const auto& p : particles) {
    centroids.insert(centroids.end(), {p.x, p.y, p.z});
    reach.insert(reach.end(), p.reach, p.reach + 6);
  }
  std::map<std::string, std::vector<double>> arrays;
  if (s_.solid()) arrays["particle_centroids"] = centroids, arrays["particle_reach"] = reach;
  if (s_.solid() && s_.solid()->reference_map().on())
    arrays["reference_map_volume"] = {s_.solid()->reference_map().volume()};
  file_.write(path + ".tmp", items,
              {{"time", s_.time},
               {"step", double(s_.step)},
               {"nx", double(g.nx)},
               {"ny", double(g.ny)},
               {"nz", double(g.nz)}},
              arrays);
  commit_file(s_.decomposition(), path + ".tmp", path);
}

std::vector<ParticleShape> Output::restart(FlowSolver& s, const std::string& path) {
  FieldFile f(s.decomposition(), s.grid());
  auto& st = s.state();
  std::vector<H5Item> items = {{"u", st.u}, {"v", st.v}, {"w", st.w}, {"p", st.p}};
  add_solid(items, s);
  auto a = f.read(path, items, {"time", "step"});
  s.time = a.at("time");
  s.step = long(a.at("step"));
  s.fill_velocity_ghosts();
  s.fill_pressure_ghosts();
  if (s.solid()) {
    s.solid()->fill_ghosts();
    s.solid()->init_force();
    if (s.solid()->reference_map().on()) {
      const std::vector<double> v = FieldFile::read_array(path, "reference_map_volume");
      if (v.size() != 1) throw InputError("restart file " + path + " holds no reference map volume");
      s.solid()->reference_map().set_volume(v[0]);
    }
    const std::vector<double> c = FieldFile::read_array(path, "particle_centroids"),
                              m = FieldFile::read_array(path, "particle_reach");
    std::vector<ParticleShape> shapes(c.size() / 3);
    for (size_t p = 0; p < shapes.size(); ++p) {
      shapes[p].x = c[3 * p], shapes[p].y = c[3 * p + 1], shapes[p].z = c[3 * p + 2];
      // a checkpoint from before the reach was stored: the seeded sphere's
      if (m.size() == 6 * shapes.size()) std::copy(&m[6 * p], &m[6 * p] + 6, shapes[p].reach);
    }
    return shapes;
  }
  return {};
}

}  // namespace softflow
