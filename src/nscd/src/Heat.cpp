// SPDX-License-Identifier: GPL-3.0-or-later
// Grain temperatures (thesis section 4.1, eq. 4.1-4.3): state, contact
// conductance and the backward-Euler heat step.
//
// The heat step of System::step: backward Euler over dt with this step's
// contact impulses,
//   (C/dt + h + L) T^{n+1} = C/dt T^n + Q + h Tf + (Dirichlet terms),
// C = m c, L the graph Laplacian of the conductances H of the contacts
// between integrated grains, Dirichlet terms from fixed-temperature walls
// and grains. The matrix is SPD: unconditionally stable and free of
// oscillations for any contact stiffness H dt / C. It is solved for the
// increment T^{n+1} - T^n by Jacobi-preconditioned conjugate gradients
// (Settings::heatTolerance, heatMaxIterations); the temperatures are then
// updated in flux form, T_i += dt/C_i (Q_i + h_i (Tf_i - T_i*) + sum_j
// H_ij (T_j* - T_i*)) with the solved T*: every contact flux enters two
// grains with opposite signs, so the heat budget (StepReport::wallHeat,
// fixedGrainHeat, sourceHeat) closes to round-off whatever the solver
// residual.
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nscd
{

namespace
{
constexpr double pi = 3.14159265358979323846;

std::string grainText(std::size_t i) { return "grain " + std::to_string(i); }
} // namespace

// ============================================================================
// state
// ============================================================================

System& SystemHeat::self() { return static_cast<System&>(*this); }
const System& SystemHeat::self() const { return static_cast<const System&>(*this); }

const std::vector<double>& SystemHeat::temperatures() const { return self().impl_->T; }
std::vector<double>& SystemHeat::temperatures() { return self().impl_->T; }

void SystemHeat::setDefaultTemperature(double T)
{
    if (!std::isfinite(T)) throw InputError("nscd::System::setDefaultTemperature: non-finite temperature");
    self().impl_->temperatureColumn().setDefault(T);
}

double SystemHeat::defaultTemperature() const { return self().impl_->temperatureColumn().defaultValue(); }

void SystemHeat::setHeatSource(std::size_t i, double Q)
{
    if (i >= self().impl_->x.size()) throw InputError("nscd::System::setHeatSource: unknown " + grainText(i));
    if (!std::isfinite(Q))
        throw InputError("nscd::System::setHeatSource: non-finite heat rate for " + grainText(i));
    self().impl_->heatQ[i] = Q;
}

double SystemHeat::heatSource(std::size_t i) const
{
    if (i >= self().impl_->x.size()) throw InputError("nscd::System::heatSource: unknown " + grainText(i));
    return self().impl_->heatQ[i];
}

void SystemHeat::setHeatExchange(std::size_t i, double h, double Tf)
{
    if (i >= self().impl_->x.size())
        throw InputError("nscd::System::setHeatExchange: unknown " + grainText(i));
    if (!(h >= 0) || !std::isfinite(h) || !std::isfinite(Tf))
    {
        std::ostringstream os;
        os << "nscd::System::setHeatExchange: need finite h >= 0 and finite Tf, got h = " << h
           << ", Tf = " << Tf << " for " << grainText(i);
        throw InputError(os.str());
    }
    self().impl_->heatH[i] = h;
    self().impl_->heatTf[i] = Tf;
}

std::pair<double, double> SystemHeat::heatExchange(std::size_t i) const
{
    if (i >= self().impl_->x.size()) throw InputError("nscd::System::heatExchange: unknown " + grainText(i));
    return {self().impl_->heatH[i], self().impl_->heatTf[i]};
}

void SystemHeat::setFixedTemperature(std::size_t i, bool fixedT)
{
    if (i >= self().impl_->x.size())
        throw InputError("nscd::System::setFixedTemperature: unknown " + grainText(i));
    self().impl_->fixT[i] = fixedT ? 1 : 0;
}

bool SystemHeat::fixedTemperature(std::size_t i) const
{
    if (i >= self().impl_->x.size())
        throw InputError("nscd::System::fixedTemperature: unknown " + grainText(i));
    return self().impl_->fixT[i] != 0;
}

double SystemHeat::heatContent(const std::vector<char>* counted) const
{
    const System::Impl& I = *self().impl_;
    if (counted && counted->size() != I.x.size())
        throw InputError("nscd::System::heatContent: " + std::to_string(counted->size()) + " flags for "
                         + std::to_string(I.x.size()) + " grains");
    double e = 0;
    for (std::size_t i = 0; i < I.x.size(); ++i)
    {
        const double c = I.materials[I.mat[i]].heatCapacity;
        if (!I.fixT[i] && c > 0 && (!counted || (*counted)[i])) e += I.mass[i] * c * I.T[i];
    }
    return e;
}

void SystemHeat::setWallTemperature(int wall, double T)
{
    if (wall < 0 || wall >= int(self().impl_->walls.size()))
        throw InputError("nscd::System::setWallTemperature: unknown wall " + std::to_string(wall));
    if (!std::isfinite(T))
        throw InputError("nscd::System::setWallTemperature: non-finite temperature for wall "
                         + std::to_string(wall) + " (use setWallAdiabatic)");
    self().impl_->walls[wall].temperature = T;
}

void SystemHeat::setWallAdiabatic(int wall)
{
    if (wall < 0 || wall >= int(self().impl_->walls.size()))
        throw InputError("nscd::System::setWallAdiabatic: unknown wall " + std::to_string(wall));
    self().impl_->walls[wall].temperature = std::numeric_limits<double>::quiet_NaN();
}

bool SystemHeat::wallAdiabatic(int wall) const
{
    if (wall < 0 || wall >= int(self().impl_->walls.size()))
        throw InputError("nscd::System::wallAdiabatic: unknown wall " + std::to_string(wall));
    return std::isnan(self().impl_->walls[wall].temperature);
}

double SystemHeat::wallTemperature(int wall) const
{
    if (wall < 0 || wall >= int(self().impl_->walls.size()))
        throw InputError("nscd::System::wallTemperature: unknown wall " + std::to_string(wall));
    return self().impl_->walls[wall].temperature;
}

// ============================================================================
// conductance (eq. 4.2-4.3)
// ============================================================================

double System::Impl::conductance(int i, int j, double rn, double dt) const
{
    // H = 4 k_s (r_n d* / (2 pi L E* dt))^(1/4), L = 1 (per unit depth in 2D;
    // the formula is used literally, see System::contactConductance).
    // k_s: harmonic mean of the conductivities (as the thesis text says);
    // walls: infinite radius and Young modulus, conductivity of the grain.
    if (!(rn > 0) || !(dt > 0)) return 0;
    const Material& mi = materials[mat[i]];
    if (!(mi.youngModulus > 0) || !(mi.conductivity > 0)) return 0;
    double invE = (1 - mi.poissonRatio * mi.poissonRatio) / mi.youngModulus;
    double invD = 1.0 / (2 * rad[i]);
    double ks = mi.conductivity;
    if (j >= 0)
    {
        const Material& mj = materials[mat[j]];
        if (!(mj.youngModulus > 0) || !(mj.conductivity > 0)) return 0;
        invE += (1 - mj.poissonRatio * mj.poissonRatio) / mj.youngModulus;
        invD += 1.0 / (2 * rad[j]);
        ks = 2.0 / (1.0 / mi.conductivity + 1.0 / mj.conductivity);
    }
    const double dstar = 1.0 / invD, Estar = 1.0 / invE;
    // x^(1/4) as two square roots: correctly rounded each, within 2 ulp of
    // pow(x, 0.25), and cheaper (pow was 2 % of the droplet run's profile)
    return 4 * ks * std::sqrt(std::sqrt(rn * dstar / (2 * pi * 1.0 * Estar * dt)));
}

// ============================================================================
// heat step
// ============================================================================

bool System::Impl::heatCheck() const
{
    const std::size_t N = x.size();
    if (T.size() != N)
    {
        std::ostringstream os;
        os << "nscd::System::step: temperatures() has " << T.size() << " entries for " << N
           << " grains (it must not be resized)";
        throw InputError(os.str());
    }
    bool active = false;
    for (std::size_t i = 0; i < N; ++i)
    {
        const double c = materials[mat[i]].heatCapacity;
        if (fixT[i] || c > 0)
        {
            if (!std::isfinite(T[i]))
                throw InputError("nscd::System::step: non-finite temperature of " + grainText(i));
            if (!fixT[i]) active = true;
        }
        else if (heatQ[i] != 0 || heatH[i] > 0)
        {
            std::ostringstream os;
            os << "nscd::System::step: " << grainText(i) << " has a heat source or exchange but its material "
               << mat[i] << " has heatCapacity 0: its temperature is not integrated (set heatCapacity > 0, "
               << "or setFixedTemperature)";
            throw InputError(os.str());
        }
    }
    return active;
}

int System::Impl::heatUnknowns(double dt)
{
    const int N = int(x.size());
    // ---- unknowns: grains with heatCapacity > 0 and no fixed temperature ----
    heatNode.assign(N, -1);
    heatGrain.clear();
    for (int i = 0; i < N; ++i)
        if (!fixT[i] && materials[mat[i]].heatCapacity > 0)
        {
            heatNode[i] = int(heatGrain.size());
            heatGrain.push_back(i);
        }
    const int n = int(heatGrain.size());
    hCap.resize(n);
    hDiag.resize(n);
    hR.resize(n);
    hZ.resize(n);
    hP.resize(n);
    hAp.resize(n);
    hX.assign(n, 0.0);
    // A = C/dt + h + L (+ bath conductances), r0 = explicit rates = b - A T^n
    for (int a = 0; a < n; ++a)
    {
        const int i = heatGrain[a];
        hCap[a] = mass[i] * materials[mat[i]].heatCapacity;
        hDiag[a] = hCap[a] / dt + heatH[i];
        hR[a] = heatQ[i] + heatH[i] * (heatTf[i] - T[i]);
    }
    return n;
}

void System::Impl::heatGraph(double dt)
{
    const int N = int(x.size());
    // ---- conduction graph from this step's contacts (eq. 4.2) ----
    heatEdges.clear();
    heatBounds.clear();
    for (const Contact& c : contacts)
    {
        if (!(c.rn > 0)) continue;
        const bool wall = c.j >= N;
        const int ci = order[c.i], cj = wall ? c.j : order[c.j]; // contacts by slot, heat by grain
        const int a = heatNode[ci];
        const int b = wall ? -1 : heatNode[cj];
        if (a < 0 && b < 0) continue; // nothing integrated
        // the other side: an unknown, a bath (fixed-temperature grain or wall), or inert
        double Tb = 0;
        if (a >= 0 && b < 0)
        {
            if (wall)
            {
                Tb = walls[c.j - N].temperature;
                if (std::isnan(Tb)) continue;
            }
            else if (fixT[cj])
                Tb = T[cj];
            else
                continue;
        }
        else if (a < 0)
        {
            if (!fixT[ci]) continue;
            Tb = T[ci];
        }
        const double H = conductance(ci, wall ? -(c.j - N + 1) : cj, c.rn, dt);
        if (!(H > 0)) continue;
        if (a >= 0 && b >= 0)
        {
            heatEdges.push_back({a, b, H});
            hDiag[a] += H;
            hDiag[b] += H;
            const double F = H * (T[cj] - T[ci]);
            hR[a] += F;
            hR[b] -= F;
        }
        else
        {
            const int u = a >= 0 ? a : b;
            heatBounds.push_back({u, H, Tb, wall});
            hDiag[u] += H;
            hR[u] += H * (Tb - T[heatGrain[u]]);
        }
    }
}

void System::Impl::heatProduct(const std::vector<double>& p, std::vector<double>& y) const
{
    const int n = int(heatGrain.size());
    for (int a = 0; a < n; ++a) y[a] = hDiag[a] * p[a];
    for (const HeatEdge& e : heatEdges)
    {
        y[e.a] -= e.H * p[e.b];
        y[e.b] -= e.H * p[e.a];
    }
}

void System::Impl::heatSolve(StepReport& rep, const HeatProduct& applyA, const HeatDot& dot,
                             const std::vector<char>& rows)
{
    const int n = int(heatGrain.size());
    // ---- solve A dT = r0 by Jacobi-preconditioned conjugate gradients ----
    const HeatProduct wholeA = [this](std::vector<double>& p, std::vector<double>& y) { heatProduct(p, y); };
    const HeatDot wholeDot = [n](const std::vector<double>& u, const std::vector<double>& v)
    {
        double s = 0;
        for (int a = 0; a < n; ++a) s += u[a] * v[a];
        return s;
    };
    const HeatProduct& A = applyA ? applyA : wholeA;
    const HeatDot& inner = dot ? dot : wholeDot;
    auto row = [&](int a) { return rows.empty() || rows[a]; };
    const double r0 = std::sqrt(inner(hR, hR));
    int it = 0;
    double res = 0;
    if (r0 > 0)
    {
        for (int a = 0; a < n; ++a)
        {
            hZ[a] = row(a) ? hR[a] / hDiag[a] : 0.0;
            hP[a] = hZ[a];
        }
        double rz = inner(hR, hZ);
        const double tol = settings.heatTolerance * r0;
        double rn = r0;
        while (it < settings.heatMaxIterations)
        {
            ++it;
            A(hP, hAp);
            const double pAp = inner(hP, hAp);
            if (!(pAp > 0)) break;
            const double alpha = rz / pAp;
            for (int a = 0; a < n; ++a)
                if (row(a))
                {
                    hX[a] += alpha * hP[a];
                    hR[a] -= alpha * hAp[a];
                }
            rn = std::sqrt(inner(hR, hR));
            if (rn <= tol) break;
            for (int a = 0; a < n; ++a) hZ[a] = row(a) ? hR[a] / hDiag[a] : 0.0;
            const double rzNew = inner(hR, hZ);
            const double beta = rzNew / rz;
            rz = rzNew;
            for (int a = 0; a < n; ++a) hP[a] = hZ[a] + beta * hP[a];
        }
        res = rn / r0;
    }
    rep.heatIterations = it;
    rep.heatResidual = res;
}

void System::Impl::heatUpdate(double dt, StepReport& rep, const std::vector<char>& rows,
                              const std::function<void(std::vector<double>&)>& toOwners)
{
    const int n = int(heatGrain.size());
    auto row = [&](int a) { return rows.empty() || rows[a]; };
    // ---- flux-form update with the implicit temperatures T* = T^n + dT ----
    // hX <- T*, hR <- heat rate into each unknown
    for (int a = 0; a < n; ++a)
    {
        const int i = heatGrain[a];
        hX[a] += T[i];
        hR[a] = 0;
        if (!row(a)) continue;
        const double exchange = heatH[i] * (heatTf[i] - hX[a]);
        hR[a] = heatQ[i] + exchange;
        rep.sourceHeat += dt * hR[a];
        rep.exchangeHeat += dt * exchange;
    }
    for (const HeatEdge& e : heatEdges)
    {
        const double F = e.H * (hX[e.b] - hX[e.a]);
        hR[e.a] += F;
        hR[e.b] -= F;
    }
    for (const HeatBoundary& bd : heatBounds)
    {
        const double F = bd.H * (bd.T - hX[bd.a]);
        hR[bd.a] += F;
        (bd.wall ? rep.wallHeat : rep.fixedGrainHeat) += dt * F;
    }
    if (toOwners) toOwners(hR);
    for (int a = 0; a < n; ++a)
        if (row(a)) T[heatGrain[a]] += dt * hR[a] / hCap[a];
}

void System::Impl::heatStep(double dt, StepReport& rep)
{
    heatUnknowns(dt);
    heatGraph(dt);
    heatSolve(rep);
    heatUpdate(dt, rep);
}

} // namespace nscd
