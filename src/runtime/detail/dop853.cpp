#include <algorithm>
#include <array>
#include <cmath>

#include <symdyn/runtime/detail/dop853.hpp>
#include <symdyn/runtime/detail/explicit_integrator.hpp>

namespace symdyn::runtime {

namespace {

// Hairer, Norsett and Wanner, Solving ODEs I, II.10 (their code DOP853).
// Nodes c_i of the 16 stages (12 of the step, 1 at its end, 3 for dense output).
constexpr double c[16] = {0.0,
                          0.526001519587677318785587544488e-01,
                          0.789002279381515978178381316732e-01,
                          0.118350341907227396726757197510,
                          0.281649658092772603273242802490,
                          0.333333333333333333333333333333,
                          0.25,
                          0.307692307692307692307692307692,
                          0.651282051282051282051282051282,
                          0.6,
                          0.857142857142857142857142857142,
                          1.0,
                          1.0,
                          0.1,
                          0.2,
                          0.777777777777777777777777777778};

// a[i][j], j < i: stage i from the slopes of stages j; row 12 holds the weights b of
// the eighth-order solution (stage 12 is f at the step end, first same as last).
constexpr double a[16][15] = {
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {5.26001519587677318785587544488e-2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2, 0, 0, 0, 0, 0, 0, 0, 0,
     0, 0, 0, 0, 0},
    {2.95875854768068491816892993775e-2, 0, 8.87627564304205475450678981324e-2, 0, 0, 0, 0, 0, 0, 0,
     0, 0, 0, 0, 0},
    {2.41365134159266685502369798665e-1, 0, -8.84549479328286085344864962717e-1,
     9.24834003261792003115737966543e-1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {3.7037037037037037037037037037e-2, 0, 0, 1.70828608729473871279604482173e-1,
     1.25467687566822425016691814123e-1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {3.7109375e-2, 0, 0, 1.70252211019544039314978060272e-1, 6.02165389804559606850219397283e-2,
     -1.7578125e-2, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {3.70920001185047927108779319836e-2, 0, 0, 1.70383925712239993810214054705e-1,
     1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
     8.27378916381402288758473766002e-3, 0, 0, 0, 0, 0, 0, 0, 0},
    {6.24110958716075717114429577812e-1, 0, 0, -3.36089262944694129406857109825,
     -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
     2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1, 0, 0, 0, 0, 0, 0, 0},
    {4.77662536438264365890433908527e-1, 0, 0, -2.48811461997166764192642586468,
     -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
     1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
     -2.03312017085086261358222928593e-2, 0, 0, 0, 0, 0, 0},
    {-9.3714243008598732571704021658e-1, 0, 0, 5.18637242884406370830023853209,
     1.09143734899672957818500254654, -8.14978701074692612513997267357,
     -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
     2.49360555267965238987089396762, -3.0467644718982195003823669022, 0, 0, 0, 0, 0},
    {2.27331014751653820792359768449, 0, 0, -1.05344954667372501984066689879e1,
     -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
     2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
     -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
     6.43392746015763530355970484046e-1, 0, 0, 0, 0},
    {5.42937341165687622380535766363e-2, 0, 0, 0, 0, 4.45031289275240888144113950566,
     1.89151789931450038304281599044, -5.8012039600105847814672114227,
     3.1116436695781989440891606237e-1, -1.52160949662516078556178806805e-1,
     2.01365400804030348374776537501e-1, 4.47106157277725905176885569043e-2, 0, 0, 0},
    {5.61675022830479523392909219681e-2, 0, 0, 0, 0, 0, 2.53500210216624811088794765333e-1,
     -2.46239037470802489917441475441e-1, -1.24191423263816360469010140626e-1,
     1.5329179827876569731206322685e-1, 8.20105229563468988491666602057e-3,
     7.56789766054569976138603589584e-3, -8.298e-3, 0, 0},
    {3.18346481635021405060768473261e-2, 0, 0, 0, 0, 2.83009096723667755288322961402e-2,
     5.35419883074385676223797384372e-2, -5.49237485713909884646569340306e-2, 0, 0,
     -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
     -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1, 0},
    {-4.28896301583791923408573538692e-1, 0, 0, 0, 0, -4.69762141536116384314449447206,
     7.68342119606259904184240953878, 4.06898981839711007970213554331,
     3.56727187455281109270669543021e-1, 0, 0, 0, -1.39902416515901462129418009734e-3,
     2.9475147891527723389556272149, -9.15095847217987001081870187138},
};

// The third-order weights are b - bhh at stages 0, 8 and 11.
constexpr double bhh0 = 0.244094488188976377952755905512, bhh8 = 0.733846688281611857341361741547,
                 bhh11 = 0.220588235294117647058823529412e-1;

// Fifth-order error weights e5 (eighth minus fifth order), on stages 0..11.
constexpr double e5[12] = {0.1312004499419488073250102996e-1,
                           0,
                           0,
                           0,
                           0,
                           -0.1225156446376204440720569753e1,
                           -0.4957589496572501915214079952,
                           0.1664377182454986536961530415e1,
                           -0.3503288487499736816886487290,
                           0.3341791187130174790297318841,
                           0.8192320648511571246570742613e-1,
                           -0.2235530786388629525884427845e-1};

// Dense output: the last four coefficients of the interpolant, d[k][j] on stage j.
constexpr double d[4][16] = {
    {-0.84289382761090128651353491142e1, 0, 0, 0, 0, 0.56671495351937776962531783590,
     -0.30689499459498916912797304727e1, 0.23846676565120698287728149680e1,
     0.21170345824450282767155149946e1, -0.87139158377797299206789907490,
     0.22404374302607882758541771650e1, 0.63157877876946881815570249290,
     -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e2,
     -0.91946323924783554000451984436e1, -0.44360363875948939664310572000e1},
    {0.10427508642579134603413151009e2, 0, 0, 0, 0, 0.24228349177525818288430175319e3,
     0.16520045171727028198505394887e3, -0.37454675472269020279518312152e3,
     -0.22113666853125306036270938578e2, 0.77334326684722638389603898808e1,
     -0.30674084731089398182061213626e2, -0.93321305264302278729567221706e1,
     0.15697238121770843886131091075e2, -0.31139403219565177677282850411e2,
     -0.93529243588444783865713862664e1, 0.35816841486394083752465898540e2},
    {0.19985053242002433820987653617e2, 0, 0, 0, 0, -0.38703730874935176555105901742e3,
     -0.18917813819516756882830838328e3, 0.52780815920542364900561016686e3,
     -0.11573902539959630126141871134e2, 0.68812326946963000169666922661e1,
     -0.10006050966910838403183860980e1, 0.77771377980534432092869265740,
     -0.27782057523535084065932004339e1, -0.60196695231264120758267380846e2,
     0.84320405506677161018159903784e2, 0.11992291136182789328035130030e2},
    {-0.25693933462703749003312586129e2, 0, 0, 0, 0, -0.15418974869023643374053993627e3,
     -0.23152937917604549567536039109e3, 0.35763911791061412378285349910e3,
     0.93405324183624310003907691704e2, -0.37458323136451633156875139351e2,
     0.10409964950896230045147246184e3, 0.29840293426660503123344363579e2,
     -0.43533456590011143754432175058e2, 0.96324553959188282948394950600e2,
     -0.39177261675615439165231486172e2, -0.14972683625798562581422125276e3},
};

class Dop853 final : public detail::ExplicitIntegrator {
 public:
  using ExplicitIntegrator::ExplicitIntegrator;
  std::string_view name() const override { return "dop853"; }

 private:
  void start(const State& initial) override {
    ExplicitIntegrator::start(initial);
    for (auto& k : k_) k.resize(x_.size());
    rejected_ = false;
  }
  double first_step(double t_end) override { return starting_step(t_end, 8, k_[1]); }
  int order() const override { return 8; }
  detail::StepOutcome attempt(double h, bool fixed) override;
  void interpolate(double t, State& s, Vector& qdd, Vector& yd) override;
  std::string stage(int i, double t, double h);
  double error_norm(double h);
  void prepare_dense_output();

  std::array<Vector, 16> k_;  // slopes of the stages (2n + m each)
  Vector xs_, x1_, slope_;
  Vector e3_;  // the third-order error estimate (error_norm's workspace)
  // The last accepted step [t_old, t_old + h_old] from x_old, and its interpolant
  // x(t_old + th·h) = r0 + th·(r1 + th1·(r2 + th·(r3 + th1·(r4 + th·(r5 + th1·(r6 + th·r7))))))
  // with th1 = 1 - th, built on the first output instant inside the step.
  Vector x_old_;
  double t_old_ = 0.0;
  double h_old_ = 0.0;
  bool dense_ready_ = false;
  std::array<Vector, 8> r_;
  bool rejected_ = false;
};

// k_i = f(t + c_i·h, x + h·sum_j a_ij·k_j), from x_old_ for the dense-output stages.
std::string Dop853::stage(int i, double t, double h) {
  const Vector& x0 = i < 13 ? x_ : x_old_;
  xs_ = x0;
  for (int j = 0; j < i; ++j) {
    if (a[i][j] != 0.0) xs_ += (h * a[i][j]) * k_[static_cast<std::size_t>(j)];
  }
  const std::string bad = derivative(t + c[i] * h, xs_, k_[static_cast<std::size_t>(i)]);
  return bad.empty() ? bad : detail::at_time(t + c[i] * h, bad);
}

// DOP853's estimate: err = |h|·e5²/sqrt(e5² + 0.01·e3²) with e5 and e3 the RMS of the
// fifth- and third-order error estimates under the weights; it behaves like an
// eighth-order error for small h and stays sane for large h.
double Dop853::error_norm(double h) {
  xs_.setZero();
  Vector& e3 = e3_;
  e3.setZero(x_.size());
  for (int j = 0; j < 12; ++j) {
    const auto& k = k_[static_cast<std::size_t>(j)];
    if (e5[j] != 0.0) xs_ += e5[j] * k;
    double b3 = a[12][j];
    if (j == 0) b3 -= bhh0;
    if (j == 8) b3 -= bhh8;
    if (j == 11) b3 -= bhh11;
    if (b3 != 0.0) e3 += b3 * k;
  }
  const double r5 = rms_scaled(xs_, x_, x1_);
  const double r3 = rms_scaled(e3, x_, x1_);
  double denominator = r5 * r5 + 0.01 * r3 * r3;
  if (denominator <= 0.0) denominator = 1.0;
  return std::abs(h) * r5 * r5 / std::sqrt(denominator);
}

detail::StepOutcome Dop853::attempt(double h, bool fixed) {
  const double t = current_.t;
  k_[0] = dx_;
  for (int i = 1; i < 12; ++i) {
    const std::string bad = stage(i, t, h);
    if (!bad.empty()) {
      rejected_ = true;
      return {false, h / 4.0, bad};
    }
  }
  x1_ = x_;
  for (int j = 0; j < 12; ++j) {
    if (a[12][j] != 0.0) x1_ += (h * a[12][j]) * k_[static_cast<std::size_t>(j)];
  }

  double next = h;
  if (!fixed) {
    const double error = error_norm(h);
    // h_new = h·0.9·err^(-1/8), its change within [1/3, 6]; no growth after a rejection.
    const double fac11 = std::pow(error, 1.0 / 8.0);
    if (error > 1.0) {
      rejected_ = true;
      return {false, h / std::min(3.0, fac11 / 0.9), {}};
    }
    next = h / std::clamp(fac11 / 0.9, 1.0 / 6.0, 3.0);
    if (rejected_) next = std::min(next, h);
    rejected_ = false;
  }
  const std::string bad = derivative(t + h, x1_, k_[12]);
  if (!bad.empty()) {
    rejected_ = true;
    return {false, h / 4.0, detail::at_time(t + h, bad)};
  }
  x_old_ = x_;
  t_old_ = t;
  h_old_ = h;
  dense_ready_ = false;
  commit(t + h, x1_, k_[12]);
  return {true, next, {}};
}

// The three extra stages and the coefficients of the seventh-order interpolant.
void Dop853::prepare_dense_output() {
  for (int i = 13; i < 16; ++i) {
    const std::string bad = stage(i, t_old_, h_old_);
    if (!bad.empty()) throw NumericError(bad + " (dense output)");
  }
  const double h = h_old_;
  r_[0] = x_old_;
  r_[1] = x_ - x_old_;
  r_[2] = h * k_[0] - r_[1];
  r_[3] = r_[1] - h * k_[12] - r_[2];
  for (int m = 0; m < 4; ++m) {
    auto& r = r_[static_cast<std::size_t>(4 + m)];
    r.setZero(x_.size());
    for (int j = 0; j < 16; ++j) {
      if (d[m][j] != 0.0) r += (h * d[m][j]) * k_[static_cast<std::size_t>(j)];
    }
  }
  dense_ready_ = true;
}

// The state from the interpolant; qdd and yd evaluated there.
void Dop853::interpolate(double t, State& s, Vector& qdd, Vector& yd) {
  if (!dense_ready_) prepare_dense_output();
  const double th = (t - t_old_) / h_old_;
  const double th1 = 1.0 - th;
  xs_ = r_[0] +
        th * (r_[1] +
              th1 * (r_[2] +
                     th * (r_[3] + th1 * (r_[4] + th * (r_[5] + th1 * (r_[6] + th * r_[7]))))));
  interpolated(t, xs_, slope_, s, qdd, yd);
}

}  // namespace

std::unique_ptr<Integrator> make_dop853(IntegratorOptions options) {
  return std::make_unique<Dop853>(std::move(options));
}

}  // namespace symdyn::runtime
