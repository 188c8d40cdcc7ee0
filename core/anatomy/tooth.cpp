#include "core/anatomy/tooth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include "core/geometry/primitives.h"

namespace sulcus {
namespace {

double Smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Polynomial smooth minimum: joins two solids with a fillet of size k.
double SMin(double a, double b, double k) {
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return b + (a - b) * h - k * h * (1 - h);
}

// Polynomial smooth maximum: intersects two solids with a rounded edge of size k.
double SMax(double a, double b, double k) { return -SMin(-a, -b, k); }

// Size of the rounding where the occlusal surface meets the crown's sides (mm).
constexpr double kEdgeRoundingMm = 0.4;

// How wide the bottom of a groove between two cusps is rounded (mm).
constexpr double kGrooveRoundingMm = 0.25;

bool Anterior(ToothType t) { return t <= ToothType::kCanine; }
bool Molar(ToothType t) { return t >= ToothType::kFirstMolar; }

// A root: a tapered cone of elliptical section (rx mesiodistal, ry bucco-lingual)
// from `top` to `apex`, rounded at the apex.
struct Root {
  Vector3 top, apex;
  double rx, ry;
};

class ToothShape {
 public:
  const std::vector<Root>& roots() const { return roots_; }
  ToothShape(const FdiTooth& t, const ToothDimensions& d)
      : type_(t.type()), upper_(t.upper()), d_(d) {
    H_ = d.crown_height;
    L_ = d.root_length;
    a_c_ = d.md_crown / 2;
    a_cx_ = d.md_cervix / 2;
    b_c_ = d.bl / 2;
    b_cx_ = d.bl / 2 * (Anterior(type_) ? 0.88 : 0.82);
    n_crown_ = Anterior(type_) ? 2.3 : 2.7;
    BuildCusps();
    if (d.roots > 1) BuildRoots();
  }

  // Signed (approximately distance-like) implicit function: negative inside.
  double operator()(const Vector3& p) const {
    double f = Body(p);
    if (!roots_.empty()) {
      f = std::max(f, furcation_ - p.z());  // the trunk ends at the furcation
      double fr = 1e9;
      for (const Root& r : roots_) fr = std::min(fr, RootDistance(r, p));
      f = SMin(f, fr, 1.0);
    }
    // The occlusal or incisal surface meets the sides in a rounded edge (the
    // marginal ridges, the incisal angles), not a crease: a crease between two
    // vertices of the mesh shows as a serrated edge.
    return SMax(f, p.z() - Occlusal(p.x(), p.y()), kEdgeRoundingMm);
  }

 private:
  // Half widths and superellipse exponent of the body's cross-section at height z.
  void Profile(double z, double* a, double* b, double* n) const {
    if (z >= 0) {
      const double u = std::min(z / H_, 1.0);
      const double rise = Smoothstep(0.0, 0.35, u);
      *a = a_cx_ + (a_c_ - a_cx_) * rise;
      *b = b_cx_ + (b_c_ - b_cx_) * Smoothstep(0.0, 0.25, u);
      if (Anterior(type_)) {
        // Labial and lingual faces converge to the incisal edge (less for canines).
        *b *= 1 - (type_ == ToothType::kCanine ? 0.55 : 0.78) * Smoothstep(0.3, 1.0, u);
      } else {
        *a *= 1 - 0.08 * Smoothstep(0.6, 1.0, u);
        *b *= 1 - 0.14 * Smoothstep(0.5, 1.0, u);  // the occlusal table is narrower
      }
      *n = n_crown_;
    } else {
      const double u = std::min(-z / L_, 1.0);
      const double taper = (1 - 0.55 * u) * std::sqrt(std::max(0.0, 1 - std::pow(u, 4)));
      *a = a_cx_ * taper;
      *b = b_cx_ * taper;
      *n = 2.0 + (n_crown_ - 2.0) * Smoothstep(-1.5, 0.0, z);
    }
  }

  double Body(const Vector3& p) const {
    if (p.z() <= -L_) return -L_ - p.z() + std::hypot(p.x(), p.y());
    double a, b, n;
    Profile(p.z(), &a, &b, &n);
    if (a < 1e-4 || b < 1e-4) return std::hypot(p.x(), p.y()) + 1e-3;
    const double r = std::pow(
        std::pow(std::abs(p.x()) / a, n) + std::pow(std::abs(p.y()) / b, n), 1.0 / n);
    return (r - 1) * std::min(a, b);
  }

  // Height of the occlusal or incisal surface above (x, y), scaled so that its
  // highest point is exactly the crown height.
  double Occlusal(double x, double y) const { return shift_ + Relief(x, y); }

  double Relief(double x, double y) const {
    switch (type_) {
      case ToothType::kCentralIncisor:
      case ToothType::kLateralIncisor:
        return -0.5 * (x / a_c_) * (x / a_c_) -
               0.3 * (y / b_c_) * (y / b_c_);  // incisal edge
      case ToothType::kCanine:
        return -2.0 * std::sqrt(x * x + 0.04) / a_c_ -
               0.3 * (y / b_c_) * (y / b_c_);  // one cusp
      default: {
        // Cusps around a central fossa: each cusp a dome, the surface the
        // highest dome (a smooth maximum), so that a groove runs where two
        // cusps meet (the central groove, the buccal and lingual grooves of a
        // molar), rounded over kGrooveRoundingMm.
        double sum = 0;
        for (const Cusp& c : cusps_) {
          const double dome =
              c.height * std::exp(-((x - c.x) * (x - c.x) + (y - c.y) * (y - c.y)) /
                                  (c.sigma * c.sigma));
          sum += std::exp(dome / kGrooveRoundingMm);
        }
        return kGrooveRoundingMm * std::log(sum);
      }
    }
  }

  struct Cusp {
    double x, y, height, sigma;
  };

  void BuildCusps() {
    const double a = a_c_, b = b_c_;
    switch (type_) {
      case ToothType::kFirstPremolar:
      case ToothType::kSecondPremolar: {
        // Buccal and lingual cusps; the lower first premolar's lingual cusp is small.
        const bool small_lingual = !upper_ && type_ == ToothType::kFirstPremolar;
        cusps_ = {{0, 0.45 * b, 2.2, 0.5 * a},
                  {0, -0.45 * b, small_lingual ? 1.0 : 1.9, 0.45 * a}};
        break;
      }
      case ToothType::kFirstMolar:
      case ToothType::kSecondMolar:
      case ToothType::kThirdMolar:
        cusps_ = {{0.45 * a, 0.45 * b, 2.3, 0.42 * a},
                  {-0.45 * a, 0.45 * b, 2.1, 0.42 * a},
                  {0.45 * a, -0.45 * b, 2.3, 0.42 * a},
                  {-0.45 * a, -0.45 * b, 2.0, 0.42 * a}};
        if (!upper_ && type_ == ToothType::kFirstMolar)
          cusps_.push_back({-0.8 * a, 0.2 * b, 1.5, 0.3 * a});  // distal
        break;
      default:
        break;
    }
    // The highest point of the relief over the crown is the crown height.
    double top = -1e9;
    for (int i = -40; i <= 40; ++i) {
      for (int j = -40; j <= 40; ++j)
        top = std::max(top, Relief(a * i / 40.0, b * j / 40.0));
    }
    shift_ = H_ - top;
  }

  void BuildRoots() {
    const double a = a_cx_, b = b_cx_;
    if (Molar(type_) && upper_) {
      // Mesiobuccal, distobuccal and palatal roots; the palatal one the longest.
      // The mesiobuccal root is broad bucco-palatally and flattened mesiodistally,
      // the distobuccal one about round, the palatal one broader mesiodistally.
      furcation_ = -3.5;
      const double palatal = d_.longest_root();
      roots_ = {{{0.45 * a, 0.4 * b, furcation_ + 1.2},
                 {0.6 * a, 0.55 * b, -L_},
                 0.16 * 2 * a,
                 0.45 * b},
                {{-0.45 * a, 0.4 * b, furcation_ + 1.2},
                 {-0.6 * a, 0.5 * b, -L_ + 0.5},
                 0.17 * 2 * a,
                 0.3 * b},
                {{0, -0.45 * b, furcation_ + 1.2},
                 {0, -0.8 * b, -palatal},
                 0.26 * 2 * a,
                 0.34 * b}};
    } else if (Molar(type_)) {
      // Mesial and distal roots, broad bucco-lingually.
      furcation_ = -3.0;
      roots_ = {
          {{0.45 * a, 0, furcation_ + 1.2}, {0.62 * a, 0, -L_}, 0.20 * 2 * a, 0.75 * b},
          {{-0.45 * a, 0, furcation_ + 1.2},
           {-0.65 * a, 0, -0.95 * L_},
           0.19 * 2 * a,
           0.7 * b}};
    } else {
      // Upper first premolar: buccal and palatal roots, split in the apical half.
      furcation_ = -0.45 * L_;
      roots_ = {{{0, 0.4 * b, furcation_ + 1.5}, {0, 0.45 * b, -L_}, 0.55 * a, 0.32 * b},
                {{0, -0.4 * b, furcation_ + 1.5},
                 {0, -0.45 * b, -L_ + 0.5},
                 0.55 * a,
                 0.32 * b}};
    }
  }

  static double RootDistance(const Root& r, const Vector3& p) {
    const Vector3 axis = r.apex - r.top;
    const double s = std::clamp((p - r.top).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
    const Vector3 d = p - (r.top + s * axis);
    const double taper = (1 - 0.5 * s) * std::sqrt(std::max(1e-6, 1 - std::pow(s, 4)));
    const double rx = r.rx * taper, ry = r.ry * taper;
    return (std::hypot(d.x() / rx, d.y() / ry) - 1) * std::min(rx, ry) +
           (s >= 1 ? std::abs(d.z()) : 0);
  }

  ToothType type_;
  bool upper_;
  ToothDimensions d_;
  double H_, L_, a_c_, a_cx_, b_c_, b_cx_, n_crown_, shift_ = 0, furcation_ = 0;
  std::vector<Cusp> cusps_;
  std::vector<Root> roots_;
};

// First point where f turns positive along the ray c + t d (t in (0, t_max]),
// found by marching and bisection.
Vector3 FirstExit(const ToothShape& f, const Vector3& c, const Vector3& d, double t_max) {
  constexpr double kStep = 0.2;
  double t_in = 0, t_out = t_max;
  for (double t = kStep; t <= t_max; t += kStep) {
    if (f(c + t * d) > 0) {
      t_out = t;
      break;
    }
    t_in = t;
  }
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (t_in + t_out);
    (f(c + mid * d) > 0 ? t_out : t_in) = mid;
  }
  return c + 0.5 * (t_in + t_out) * d;
}

}  // namespace

FdiTooth FdiTooth::Parse(int fdi) {
  const int q = fdi / 10, pos = fdi % 10;
  if (fdi < 11 || fdi > 48) {
    throw std::invalid_argument(
        "FDI " + std::to_string(fdi) +
        " does not exist: expected 11 to 48 (quadrant 1 to 4, then tooth 1 to 8)");
  }
  if (q < 1 || q > 4) {
    throw std::invalid_argument("FDI " + std::to_string(fdi) +
                                " does not exist: the quadrant digit is 1 to 4");
  }
  if (pos < 1 || pos > 8) {
    throw std::invalid_argument("FDI " + std::to_string(fdi) +
                                " does not exist: the tooth digit is 1 to 8");
  }
  return {fdi, q, pos};
}

std::string ToString(ToothType t) {
  static const char* names[] = {"central incisor", "lateral incisor", "canine",
                                "first premolar",  "second premolar", "first molar",
                                "second molar",    "third molar"};
  return names[static_cast<int>(t)];
}

ToothDimensions Dimensions(const FdiTooth& t) {
  // crown height, root length, MD crown, MD cervix, BL, roots, palatal root (typical
  // adult values).
  static const ToothDimensions upper[8] = {
      {10.5, 13, 8.5, 7.0, 7.0, 1}, {9.0, 13, 6.5, 5.0, 6.0, 1},
      {10.0, 17, 7.5, 5.5, 8.0, 1}, {8.5, 14, 7.0, 5.0, 9.0, 2},
      {8.5, 14, 6.5, 5.0, 9.0, 1},  {7.5, 12, 10.0, 8.0, 11.0, 3, 13},
      {7.0, 11, 9.0, 7.0, 11.0, 3}, {6.5, 10, 8.5, 6.5, 10.0, 3}};
  static const ToothDimensions lower[8] = {
      {9.0, 12.5, 5.0, 3.5, 6.0, 1}, {9.5, 14, 5.5, 4.0, 6.5, 1},
      {11.0, 16, 7.0, 5.5, 7.5, 1},  {8.5, 14, 7.0, 5.0, 7.5, 1},
      {8.0, 14.5, 7.0, 5.0, 8.0, 1}, {7.5, 14, 11.0, 9.0, 10.5, 2},
      {7.0, 13, 10.5, 8.0, 10.0, 2}, {6.5, 12, 10.0, 7.5, 9.5, 2}};
  return (t.upper() ? upper : lower)[t.position - 1];
}

namespace {

ToothModel MakeTooth(int fdi, const ToothParams& params) {
  ToothModel m;
  m.tooth = FdiTooth::Parse(fdi);
  m.dimensions = Dimensions(m.tooth);
  const ToothShape shape(m.tooth, m.dimensions);
  for (const Root& r : shape.roots()) m.root_tops.push_back(r.top);
  const ToothDimensions& d = m.dimensions;
  // Rays from a point inside the crown, spread like the vertices of an ellipsoid of
  // the tooth's proportions so that the long root gets its share.
  const Vector3 c(0, 0, 0.35 * d.crown_height);
  const Vector3 stretch(d.md_crown / 2, d.bl / 2, 0.5 * (d.crown_height + d.root_length));
  TriangleMesh sphere = MakeIcosphere(1.0, params.resolution);
  std::vector<Vector3> vertices;
  vertices.reserve(sphere.num_vertices());
  const double t_max = 2 * (d.crown_height + d.root_length + 2);
  for (const Vector3& u : sphere.vertices()) {
    vertices.push_back(FirstExit(shape, c, stretch.cwiseProduct(u).normalized(), t_max));
  }
  m.mesh = TriangleMesh(std::move(vertices), sphere.faces());
  // The CEJ: scalloped, higher at the proximal (mesial, distal) surfaces.
  const double scallop = Anterior(m.tooth.type()) ? 1.5 : 0.8;
  for (int i = 0; i < 72; ++i) {
    const double th = 2 * std::numbers::pi * i / 72;
    const Vector3 start(0, 0, scallop * std::cos(th) * std::cos(th));
    m.cej.push_back(
        FirstExit(shape, start, Vector3(std::cos(th), std::sin(th), 0), 20.0));
  }
  return m;
}

}  // namespace

ToothModel GenerateTooth(int fdi, const ToothParams& params) {
  if (params.resolution < 2 || params.resolution > 7) {
    throw std::invalid_argument("tooth resolution " + std::to_string(params.resolution) +
                                " is out of range (2 to 7)");
  }
  // A scene's compile asks for the same tooth again and again (each share of
  // the gingiva, its neighbours', the effects' collars), and the answer never
  // changes: each tooth is made once per resolution (at most 32 x 6 of them).
  static std::mutex mutex;
  static std::map<std::pair<int, int>, ToothModel> made;
  const std::pair key(fdi, params.resolution);
  {
    std::lock_guard lock(mutex);
    if (const auto it = made.find(key); it != made.end()) return it->second;
  }
  ToothModel m = MakeTooth(fdi, params);  // (throws for a number that is not a tooth)
  std::lock_guard lock(mutex);
  made.try_emplace(key, m);
  return m;
}

}  // namespace sulcus
