#include "sim/blast/reflection.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

namespace brisance::blast {

namespace {

// --- The charts ------------------------------------------------------------------------------
// UFC 3-340-02 (2008), "Structures to Resist the Effects of Accidental Explosions", figs. 2-193
// (reflected pressure coefficient versus angle of incidence) and 2-194 (scaled reflected impulse
// versus angle of incidence), one curve per incident overpressure. Values come from the public
// digitisation of these charts in the ufc-blast-calculator project (Nyobir, MIT licence), reduced
// here to the points needed to follow each curve within 0.03 in C_R (its digitising noise), each
// curve ended at exactly C_R = 1 at 90 degrees (four curves stop short of it in the chart), and
// fig. 2-194 resampled every 5 degrees as a ratio to its value at 0 degrees. Pressures in Pa.

struct PressureCurve {
  double incident_overpressure_pa;
  double peak_angle_deg;  // angle of the Mach-stem peak (largest C_R beyond 25 degrees)
  std::vector<std::array<double, 2>> points;  // {angle_deg, C_R}, angle ascending 0..90
};

const std::vector<PressureCurve>& pressure_chart() {
  // clang-format off
  static const std::vector<PressureCurve> chart = {
    {1378.95, 79.97, {{0.00, 1.9994}, {68.29, 1.9994}, {74.54, 2.1741}, {75.73, 2.3480}, {78.83, 3.0030}, {79.97, 3.0380}, {81.11, 2.8961}, {84.99, 1.7288}, {90.00, 1.0000}}},
    {3447.38, 74.16, {{0.00, 2.0661}, {62.89, 2.0634}, {68.81, 2.2903}, {69.87, 2.3919}, {73.10, 3.0378}, {74.16, 3.0835}, {75.71, 2.9240}, {79.61, 2.2109}, {84.37, 1.5432}, {90.00, 1.0000}}},
    {6894.76, 69.12, {{0.00, 2.0928}, {10.01, 2.0928}, {11.73, 2.0564}, {13.60, 2.0928}, {54.83, 2.0768}, {62.37, 2.2484}, {63.36, 2.3155}, {64.32, 2.4068}, {67.63, 3.0180}, {68.56, 3.1270}, {69.12, 3.1403}, {70.61, 3.0197}, {74.52, 2.4256}, {79.14, 1.8927}, {80.02, 1.7503}, {85.67, 1.2574}, {90.00, 1.0000}}},
    {13789.5, 62.91, {{0.00, 2.1195}, {49.58, 2.1391}, {52.81, 2.2138}, {57.05, 2.4141}, {60.30, 2.8758}, {62.10, 3.0854}, {62.91, 3.0985}, {64.57, 2.9863}, {75.22, 1.8854}, {84.44, 1.2404}, {90.00, 1.0000}}},
    {34473.8, 52.61, {{0.00, 2.1995}, {40.95, 2.2043}, {43.73, 2.3522}, {45.95, 2.3668}, {47.62, 2.4801}, {49.84, 2.7305}, {52.61, 3.2324}, {62.61, 2.3916}, {65.38, 2.2164}, {66.19, 2.1164}, {67.81, 2.0361}, {68.41, 1.9570}, {75.63, 1.5684}, {90.00, 1.0000}}},
    {68947.6, 46.40, {{0.00, 2.5067}, {39.79, 2.4941}, {43.48, 2.7511}, {46.40, 3.2373}, {47.21, 3.2264}, {52.61, 2.5911}, {55.99, 2.2777}, {61.92, 1.9069}, {70.23, 1.5460}, {72.85, 1.5023}, {81.38, 1.1920}, {90.00, 1.0000}}},
    {137895, 42.92, {{0.00, 2.9997}, {10.42, 2.9972}, {22.68, 2.8699}, {30.71, 2.8566}, {36.06, 2.9015}, {38.68, 2.9821}, {39.79, 3.0385}, {42.92, 3.3331}, {47.21, 2.7263}, {52.70, 2.1761}, {55.99, 1.9412}, {64.32, 1.5915}, {73.96, 1.2702}, {79.14, 1.2142}, {90.00, 1.0000}}},
    {206843, 40.75, {{0.00, 3.3464}, {23.62, 3.1080}, {33.46, 3.0980}, {37.72, 3.1890}, {40.75, 3.5981}, {43.43, 2.9754}, {45.80, 2.6262}, {53.02, 1.9406}, {56.79, 1.7205}, {64.22, 1.4423}, {73.86, 1.2071}, {90.00, 1.0000}}},
    {344738, 40.35, {{0.00, 3.9961}, {35.50, 3.4931}, {37.17, 3.5568}, {37.99, 3.6401}, {39.79, 4.0441}, {40.35, 4.0975}, {40.90, 4.0120}, {42.10, 3.6205}, {44.87, 2.9557}, {46.81, 2.6753}, {51.02, 2.1928}, {53.92, 1.9668}, {65.65, 1.4142}, {80.93, 1.0973}, {90.00, 1.0000}}},
    {482633, 40.40, {{0.00, 4.4467}, {9.31, 4.3557}, {25.41, 4.0914}, {34.29, 3.8487}, {37.62, 3.9332}, {38.18, 3.9799}, {40.40, 4.3291}, {40.95, 4.2533}, {43.73, 3.5659}, {46.51, 3.1057}, {49.88, 2.7034}, {56.98, 2.0631}, {63.72, 1.7121}, {71.49, 1.3987}, {78.00, 1.2089}, {90.00, 1.0000}}},
    {689476, 40.35, {{0.00, 5.0079}, {15.23, 4.7947}, {36.06, 4.2521}, {37.85, 4.2966}, {40.35, 4.7128}, {40.87, 4.7027}, {45.65, 3.8258}, {48.32, 3.4192}, {57.46, 2.3565}, {62.68, 1.9334}, {74.87, 1.4110}, {90.00, 1.0000}}},
    {1.03421e+06, 41.12, {{0.00, 5.6026}, {16.11, 5.3192}, {24.61, 5.0658}, {34.39, 4.6000}, {37.48, 4.6239}, {39.79, 4.8746}, {41.12, 5.1703}, {42.09, 5.1176}, {48.07, 4.3382}, {54.24, 3.4376}, {59.78, 2.5456}, {62.52, 2.1857}, {68.31, 1.7818}, {73.71, 1.5957}, {75.43, 1.3858}, {77.11, 1.2830}, {83.04, 1.1067}, {90.00, 1.0000}}},
    {1.37895e+06, 41.56, {{0.00, 6.0021}, {20.26, 5.6391}, {28.17, 5.2947}, {34.39, 4.9383}, {36.06, 4.9019}, {37.72, 4.9441}, {39.79, 5.1292}, {41.56, 5.4857}, {43.43, 5.4020}, {47.16, 4.9838}, {49.18, 4.6823}, {60.00, 2.7888}, {63.21, 2.3383}, {67.43, 1.9481}, {74.39, 1.5247}, {90.00, 1.0000}}},
    {2.06843e+06, 43.62, {{0.00, 6.6543}, {8.38, 6.5386}, {20.11, 6.1919}, {34.39, 5.3784}, {37.17, 5.2687}, {37.99, 5.2624}, {39.79, 5.3857}, {40.90, 5.5875}, {42.09, 5.9277}, {42.86, 6.0193}, {43.62, 6.0439}, {46.06, 5.8344}, {48.07, 5.5336}, {52.36, 4.6340}, {57.16, 3.4737}, {60.99, 2.6877}, {63.12, 2.1851}, {67.52, 1.5173}, {71.21, 1.2259}, {78.26, 1.0320}, {90.00, 1.0000}}},
    {2.7579e+06, 45.24, {{0.00, 6.9933}, {5.42, 6.9424}, {15.41, 6.7320}, {24.85, 6.3059}, {35.96, 5.6027}, {38.18, 5.5008}, {39.84, 5.5021}, {40.40, 5.5772}, {42.06, 5.9391}, {43.58, 6.3550}, {44.69, 6.5453}, {45.24, 6.5744}, {46.35, 6.4320}, {48.58, 5.9603}, {50.24, 5.5354}, {56.85, 3.6507}, {61.28, 2.6640}, {63.20, 2.1854}, {68.50, 1.3981}, {71.32, 1.2451}, {78.46, 1.0309}, {90.00, 1.0000}}},
    {3.44738e+06, 44.97, {{0.00, 7.7982}, {5.07, 7.6450}, {15.23, 7.2366}, {25.76, 6.6537}, {32.85, 6.1379}, {36.06, 5.8500}, {39.79, 5.7064}, {41.28, 5.8220}, {41.93, 5.9362}, {42.62, 6.1134}, {44.97, 7.0733}, {45.75, 7.0218}, {48.40, 6.4530}, {49.78, 6.0704}, {52.36, 5.3022}, {56.95, 3.7659}, {61.05, 2.7320}, {62.62, 2.2964}, {63.93, 2.0612}, {68.06, 1.4525}, {71.62, 1.2450}, {75.97, 1.0928}, {80.05, 1.0098}, {90.00, 1.0000}}},
    {6.89476e+06, 46.28, {{0.00, 8.6002}, {9.31, 8.2785}, {19.35, 7.6919}, {27.91, 7.0723}, {36.06, 6.3962}, {40.70, 6.0826}, {43.07, 6.1004}, {43.57, 6.1834}, {43.88, 6.3286}, {44.06, 6.5205}, {45.22, 7.2037}, {45.85, 7.5159}, {46.28, 7.5852}, {48.37, 7.0764}, {52.36, 5.7988}, {55.54, 4.5076}, {57.71, 3.6907}, {61.60, 2.5986}, {63.56, 2.1166}, {66.18, 1.7154}, {70.05, 1.3003}, {73.09, 1.1897}, {80.05, 0.9960}, {90.00, 1.0000}}},
    {1.37895e+07, 25.19, {{0.00, 10.0000}, {5.07, 9.9449}, {9.86, 9.8018}, {15.38, 9.5318}, {19.66, 9.2223}, {25.19, 8.7333}, {33.72, 7.7848}, {37.98, 7.2597}, {42.01, 6.8779}, {43.63, 6.8708}, {44.80, 7.0789}, {45.35, 7.3645}, {45.65, 7.6882}, {46.10, 8.0332}, {46.64, 8.2254}, {47.46, 8.1542}, {48.13, 8.0032}, {49.96, 7.3687}, {56.70, 4.4244}, {59.65, 3.3104}, {62.03, 2.4537}, {63.51, 2.1304}, {66.39, 1.7015}, {70.00, 1.3003}, {80.00, 0.9960}, {90.00, 1.0000}}},
    {2.06843e+07, 25.86, {{0.00, 10.8032}, {9.86, 10.5517}, {15.26, 10.2820}, {20.11, 9.9364}, {28.97, 8.9310}, {39.79, 7.5262}, {41.46, 7.3558}, {42.92, 7.2782}, {43.48, 7.2600}, {45.07, 7.4307}, {46.40, 8.4950}, {46.81, 8.6258}, {47.21, 8.6316}, {47.90, 8.5074}, {50.16, 7.6316}, {52.63, 6.3426}, {54.51, 5.4958}, {56.27, 4.5933}, {56.80, 4.3676}, {59.79, 3.2648}, {62.93, 2.2272}, {66.91, 1.6047}, {68.95, 1.3833}, {71.73, 1.2450}, {80.00, 1.0098}, {90.00, 1.0000}}},
    {3.44738e+07, 25.05, {{0.00, 12.2412}, {4.91, 11.9957}, {9.15, 11.7036}, {15.51, 11.1393}, {25.05, 10.0388}, {33.52, 8.9130}, {43.06, 7.5434}, {45.38, 7.3389}, {46.30, 7.4536}, {46.62, 7.8052}, {46.69, 8.1051}, {46.84, 8.4543}, {46.94, 8.8126}, {47.60, 9.0392}, {48.53, 8.8645}, {50.07, 8.3070}, {52.49, 7.1942}, {57.11, 4.6558}, {60.21, 3.2266}, {61.30, 2.7681}, {62.87, 2.2369}, {68.21, 1.4408}, {72.04, 1.2422}, {80.01, 1.0112}, {90.00, 1.0000}}},
  };
  // clang-format on
  return chart;
}

constexpr int kImpulseAngles = 19;  // 0, 5, ..., 90 degrees
struct ImpulseCurve {
  double incident_overpressure_pa;
  std::array<double, kImpulseAngles> ratio;  // i_r(alpha) / i_r(0)
};

// clang-format off
constexpr std::array kImpulseChart = {
    ImpulseCurve{4826.33, {1.0000, 0.9948, 0.9948, 0.9824, 0.9792, 0.9666, 0.9518, 0.9354, 0.9144, 0.8924, 0.8672, 0.8380, 0.8064, 0.7717, 0.7332, 0.6929, 0.6496, 0.6047, 0.5597}},
    ImpulseCurve{6894.76, {1.0000, 0.9948, 0.9948, 0.9823, 0.9763, 0.9644, 0.9483, 0.9297, 0.9091, 0.8849, 0.8583, 0.8293, 0.7962, 0.7607, 0.7224, 0.6824, 0.6385, 0.5943, 0.5489}},
    ImpulseCurve{10342.1, {1.0000, 0.9964, 0.9948, 0.9826, 0.9763, 0.9621, 0.9456, 0.9254, 0.9035, 0.8781, 0.8489, 0.8187, 0.7844, 0.7480, 0.7091, 0.6683, 0.6245, 0.5804, 0.5345}},
    ImpulseCurve{13789.5, {1.0000, 1.0017, 0.9923, 0.9874, 0.9775, 0.9609, 0.9433, 0.9225, 0.8983, 0.8707, 0.8419, 0.8089, 0.7743, 0.7374, 0.6976, 0.6567, 0.6136, 0.5701, 0.5233}},
    ImpulseCurve{20684.3, {1.0000, 0.9990, 0.9923, 0.9825, 0.9710, 0.9540, 0.9364, 0.9131, 0.8873, 0.8582, 0.8266, 0.7927, 0.7564, 0.7183, 0.6780, 0.6365, 0.5940, 0.5509, 0.5089}},
    ImpulseCurve{34473.8, {1.0000, 0.9994, 0.9873, 0.9773, 0.9630, 0.9464, 0.9240, 0.8996, 0.8701, 0.8397, 0.8056, 0.7693, 0.7308, 0.6914, 0.6501, 0.6077, 0.5660, 0.5238, 0.4838}},
    ImpulseCurve{68947.6, {1.0000, 0.9967, 0.9923, 0.9799, 0.9632, 0.9402, 0.9157, 0.8852, 0.8522, 0.8165, 0.7795, 0.7390, 0.6980, 0.6553, 0.6129, 0.5705, 0.5284, 0.4873, 0.4499}},
    ImpulseCurve{137895, {1.0000, 0.9963, 0.9847, 0.9706, 0.9533, 0.9271, 0.8987, 0.8646, 0.8280, 0.7879, 0.7460, 0.7022, 0.6576, 0.6134, 0.5688, 0.5258, 0.4843, 0.4456, 0.4080}},
    ImpulseCurve{344738, {1.0000, 0.9948, 0.9842, 0.9698, 0.9450, 0.9155, 0.8825, 0.8432, 0.8012, 0.7563, 0.7094, 0.6608, 0.6130, 0.5653, 0.5193, 0.4754, 0.4347, 0.3967, 0.3654}},
    ImpulseCurve{689476, {1.0000, 0.9952, 0.9838, 0.9634, 0.9393, 0.9067, 0.8706, 0.8277, 0.7822, 0.7337, 0.6836, 0.6315, 0.5808, 0.5311, 0.4840, 0.4395, 0.3991, 0.3629, 0.3311}},
    ImpulseCurve{1.37895e+06, {1.0000, 0.9891, 0.9773, 0.9566, 0.9276, 0.8898, 0.8464, 0.7984, 0.7461, 0.6902, 0.6339, 0.5771, 0.5216, 0.4681, 0.4187, 0.3734, 0.3334, 0.2999, 0.2741}},
    ImpulseCurve{2.7579e+06, {1.0000, 0.9962, 0.9763, 0.9477, 0.9084, 0.8580, 0.8004, 0.7368, 0.6691, 0.5977, 0.5262, 0.4553, 0.3881, 0.3258, 0.2701, 0.2225, 0.1838, 0.1563, 0.1386}},
    ImpulseCurve{4.82633e+06, {1.0000, 0.9920, 0.9720, 0.9399, 0.8953, 0.8413, 0.7782, 0.7078, 0.6327, 0.5553, 0.4768, 0.4007, 0.3285, 0.2623, 0.2043, 0.1558, 0.1183, 0.0925, 0.0791}},
    ImpulseCurve{6.89476e+06, {1.0000, 0.9924, 0.9718, 0.9385, 0.8928, 0.8363, 0.7704, 0.6980, 0.6204, 0.5406, 0.4598, 0.3815, 0.3075, 0.2400, 0.1810, 0.1321, 0.0946, 0.0704, 0.0588}},
    ImpulseCurve{1.03421e+07, {1.0000, 0.9909, 0.9718, 0.9371, 0.8900, 0.8325, 0.7653, 0.6912, 0.6124, 0.5306, 0.4486, 0.3684, 0.2934, 0.2247, 0.1652, 0.1159, 0.0789, 0.0547, 0.0439}},
    ImpulseCurve{1.37895e+07, {1.0000, 0.9922, 0.9710, 0.9359, 0.8895, 0.8305, 0.7625, 0.6878, 0.6076, 0.5256, 0.4427, 0.3624, 0.2868, 0.2179, 0.1583, 0.1091, 0.0721, 0.0482, 0.0376}},
    ImpulseCurve{2.06843e+07, {1.0000, 0.9882, 0.9660, 0.9306, 0.8840, 0.8253, 0.7581, 0.6822, 0.6025, 0.5205, 0.4379, 0.3574, 0.2819, 0.2134, 0.1537, 0.1049, 0.0680, 0.0444, 0.0342}},
    ImpulseCurve{2.7579e+07, {1.0000, 0.9991, 0.9760, 0.9407, 0.8929, 0.8341, 0.7652, 0.6897, 0.6088, 0.5260, 0.4424, 0.3614, 0.2853, 0.2159, 0.1559, 0.1064, 0.0691, 0.0453, 0.0349}},
    ImpulseCurve{3.44738e+07, {1.0000, 0.9893, 0.9666, 0.9319, 0.8838, 0.8264, 0.7589, 0.6837, 0.6046, 0.5216, 0.4390, 0.3588, 0.2838, 0.2150, 0.1553, 0.1064, 0.0696, 0.0459, 0.0355}},
    ImpulseCurve{4.13685e+07, {1.0000, 0.9947, 0.9718, 0.9370, 0.8878, 0.8301, 0.7617, 0.6868, 0.6064, 0.5241, 0.4409, 0.3605, 0.2847, 0.2160, 0.1559, 0.1067, 0.0697, 0.0459, 0.0355}},
    ImpulseCurve{4.82633e+07, {1.0000, 0.9914, 0.9706, 0.9349, 0.8870, 0.8283, 0.7593, 0.6842, 0.6041, 0.5208, 0.4382, 0.3573, 0.2815, 0.2128, 0.1525, 0.1033, 0.0665, 0.0428, 0.0327}},
};
// clang-format on

double curve_value(const PressureCurve& curve, double angle_deg) {
  const auto& pts = curve.points;
  const auto upper =
      std::upper_bound(pts.begin(), pts.end(), angle_deg,
                       [](double a, const std::array<double, 2>& p) { return a < p[0]; });
  if (upper == pts.begin()) return pts.front()[1];
  if (upper == pts.end()) return pts.back()[1];
  const auto& lo = *(upper - 1);
  const auto& hi = *upper;
  return lo[1] + (hi[1] - lo[1]) * (angle_deg - lo[0]) / (hi[0] - lo[0]);
}

// Maps an angle on a curve whose peak is at `from_peak` to the same place on a curve whose peak
// is at `to_peak`, stretching [0, peak] and [peak, 90] separately.
double align(double angle_deg, double from_peak, double to_peak) {
  if (angle_deg <= from_peak) return angle_deg * to_peak / from_peak;
  return to_peak + (angle_deg - from_peak) * (90.0 - to_peak) / (90.0 - from_peak);
}

// The bracketing pair of curves for a pressure, and the weight of the upper one in log P.
struct Bracket {
  std::size_t lower;
  double weight;
  bool in_range;
};

template <typename Curves>
Bracket bracket(const Curves& curves, double pressure_pa) {
  const std::size_t last = curves.size() - 1;
  if (!(pressure_pa > curves.front().incident_overpressure_pa))
    return {0, 0.0, pressure_pa >= curves.front().incident_overpressure_pa * (1 - 1e-12)};
  if (pressure_pa >= curves[last].incident_overpressure_pa)
    return {last - 1, 1.0, pressure_pa <= curves[last].incident_overpressure_pa * (1 + 1e-12)};
  std::size_t i = 0;
  while (curves[i + 1].incident_overpressure_pa <= pressure_pa)
    ++i;
  const double lo = curves[i].incident_overpressure_pa;
  const double hi = curves[i + 1].incident_overpressure_pa;
  return {i, std::log(pressure_pa / lo) / std::log(hi / lo), true};
}

double to_degrees(double angle_rad) {
  return std::clamp(angle_rad * 180.0 / std::numbers::pi, 0.0, 90.0);
}

}  // namespace

ChartValue chart_impulse_ratio(double incident_overpressure_pa, double angle_rad) {
  assert(incident_overpressure_pa > 0.0);
  const Bracket b = bracket(kImpulseChart, incident_overpressure_pa);
  const double angle_deg = to_degrees(angle_rad);
  const double position = std::clamp(angle_deg / 5.0, 0.0, kImpulseAngles - 1.0);
  const int k = std::min(static_cast<int>(position), kImpulseAngles - 2);
  const double f = position - k;
  auto at = [&](const ImpulseCurve& curve) {
    return curve.ratio[k] + f * (curve.ratio[k + 1] - curve.ratio[k]);
  };
  return {at(kImpulseChart[b.lower]) * (1 - b.weight) + at(kImpulseChart[b.lower + 1]) * b.weight,
          b.in_range};
}

ChartValue chart_reflection_coefficient(double incident_overpressure_pa, double angle_rad) {
  assert(incident_overpressure_pa > 0.0);
  const double angle_deg = to_degrees(angle_rad);
  const auto& chart = pressure_chart();
  const Bracket b = bracket(chart, incident_overpressure_pa);
  const PressureCurve& lower = chart[b.lower];
  const PressureCurve& upper = chart[b.lower + 1];
  // Interpolating two curves at the same angle would smear the Mach-stem peak into two small
  // bumps, because the peak moves from about 80 degrees at 1 kPa to 40 degrees at 300 kPa; so
  // each curve is read at the angle that sits in the same place relative to its own peak.
  const double peak =
      lower.peak_angle_deg + b.weight * (upper.peak_angle_deg - lower.peak_angle_deg);
  const double value_lower = curve_value(lower, align(angle_deg, peak, lower.peak_angle_deg));
  const double value_upper = curve_value(upper, align(angle_deg, peak, upper.peak_angle_deg));
  // A few digitised points near grazing read 0.996; a reflection never lowers the pressure.
  return {std::max(1.0, value_lower + b.weight * (value_upper - value_lower)), b.in_range};
}

ObliqueReflection oblique_reflection(double incident_overpressure_pa, double incident_impulse_pa_s,
                                     double normal_reflected_pa,
                                     double normal_reflected_impulse_pa_s, double angle_rad) {
  assert(incident_overpressure_pa > 0.0 && normal_reflected_pa >= incident_overpressure_pa);
  const ChartValue chart_normal = chart_reflection_coefficient(incident_overpressure_pa, 0.0);
  const ChartValue chart_angle = chart_reflection_coefficient(incident_overpressure_pa, angle_rad);
  // The chart's shape between its own ends, C_R(0) and 1, stretched onto the curves' ends.
  const double normal_coefficient = normal_reflected_pa / incident_overpressure_pa;
  const double shape = (chart_angle.value - 1.0) / (chart_normal.value - 1.0);
  ObliqueReflection out;
  out.coefficient = 1.0 + (normal_coefficient - 1.0) * shape;
  out.overpressure_pa = out.coefficient * incident_overpressure_pa;
  // Fig. 2-194 likewise gives the shape of the impulse from i_r at 0 degrees to its grazing
  // value, which matches the side-on impulse i_s (its 90-degree ratio is i_s / i_r of the
  // curves to a few percent); stretched onto [i_s, i_r] so both ends are exact.
  const double grazing = chart_impulse_ratio(incident_overpressure_pa, std::numbers::pi / 2).value;
  const double impulse_shape =
      (chart_impulse_ratio(incident_overpressure_pa, angle_rad).value - grazing) / (1.0 - grazing);
  out.impulse_pa_s = incident_impulse_pa_s +
                     (normal_reflected_impulse_pa_s - incident_impulse_pa_s) * impulse_shape;
  out.in_chart_range = chart_angle.in_range;
  return out;
}

}  // namespace brisance::blast
