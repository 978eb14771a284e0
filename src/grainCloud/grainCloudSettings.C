// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud settings (see grainCloud.H)

Description
    constant/grainProperties read and checked (FatalIOError naming the file,
    the keyword and the fix): the top-level keywords, the materials (density
    [kg/m^3], friction [-], youngModulus [Pa], poissonRatio [-], conductivity
    [W/(m K)], heatCapacity [J/(kg K)], contact compliance [m/N] or
    relativeCompliance [-]), the contactSolver settings, and the
    replacement of a saved state's materials by those of the dictionary.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "grainDictionaryTools.H"
#include "OStringStream.H"
#include <cmath>

#include <initializer_list>
#include <utility>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
// contactSolver.<key>: the value of the named choice, among names (in the
// order the error message lists them); current if key is not given
template<class Choice>
Choice contactSolverChoice
(
    const Foam::dictionary& cs,
    const char* key,
    const Choice current,
    std::initializer_list<std::pair<const char*, Choice>> names
)
{
    if (!cs.found(key))
    {
        return current;
    }
    const Foam::word w(cs.get<Foam::word>(key));
    for (const auto& n : names)
    {
        if (w == n.first) return n.second;
    }
    Foam::OStringStream list;
    for (const auto& n : names)
    {
        list << (&n == names.begin() ? "" : ", ") << n.first;
    }
    FatalIOErrorInFunction(cs)
        << "unknown contactSolver " << key << " " << w
        << "; " << key << "s: " << list.str().c_str()
        << Foam::exit(Foam::FatalIOError);
    return names.begin()->second;
}
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::grainCloud::readSettings()
{
    grainTools::checkUniqueKeywords(dict_);
    grainTools::checkKeywords
    (
        dict_,
        {
            "materials", "wallPatches", "wallFriction",
            "maxDisplacementFraction",
            "contactSolver", "movingWalls", "initialTemperature",
            "wallTemperatures", "gates", "frontRearWalls", "outletPatches",
            "grainDecomposition"
        }
    );

    maxDisplacementFraction_ =
        grainTools::getPositiveOrDefault(dict_, "maxDisplacementFraction", 0.1);
    if (maxDisplacementFraction_ > 0.5)
    {
        FatalIOErrorInFunction(dict_)
            << "maxDisplacementFraction " << maxDisplacementFraction_
            << " in " << dict_.name() << " is too large: grains could cross"
            << " each other within a sub-step. Use a value <= 0.5 (0.1 is"
            << " the default)." << exit(FatalIOError);
    }

    const dictionary& mats = dict_.subDict("materials");
    if (mats.empty())
    {
        FatalIOErrorInFunction(mats)
            << "No material in " << mats.name()
            << ". Add e.g. glass { density 2500; friction 0.4; }"
            << exit(FatalIOError);
    }
    for (const entry& e : mats)
    {
        if (!e.isDict())
        {
            FatalIOErrorInFunction(mats)
                << "Entry '" << e.keyword() << "' of " << mats.name()
                << " must be a dictionary { density ...; friction ...; }"
                << exit(FatalIOError);
        }
        grainTools::checkKeywords
        (
            e.dict(),
            {
                "density", "friction", "youngModulus", "poissonRatio",
                "conductivity", "heatCapacity", "compliance",
                "relativeCompliance"
            }
        );
        // contact compliance (nscd::Material): >= 0, one of the two
        for (const char* key : {"compliance", "relativeCompliance"})
        {
            const scalar c = e.dict().getOrDefault<scalar>(key, 0);
            if (!(c >= 0) || !std::isfinite(c))
            {
                FatalIOErrorInFunction(e.dict())
                    << key << " of material " << e.keyword() << " in "
                    << dict_.name() << " must be finite and >= 0, got " << c
                    << nl << "    compliance [m/N] (2D: [m^2/N], per unit"
                    << " depth) = allowed overlap / reference normal load;"
                    << " relativeCompliance [-] = beta, relative to the"
                    << " contact's Delassus diagonal; 0 (default): hard"
                    << " contact" << exit(FatalIOError);
            }
        }
        if
        (
            e.dict().getOrDefault<scalar>("compliance", 0) > 0
         && e.dict().getOrDefault<scalar>("relativeCompliance", 0) > 0
        )
        {
            FatalIOErrorInFunction(e.dict())
                << "material " << e.keyword() << " in " << dict_.name()
                << " gives both compliance and relativeCompliance: give one"
                << " of the two (or neither, for hard contacts)"
                << exit(FatalIOError);
        }
        const scalar mu = e.dict().get<scalar>("friction");
        if (mu < 0)
        {
            FatalIOErrorInFunction(e.dict())
                << "friction of material " << e.keyword() << " must be >= 0"
                << exit(FatalIOError);
        }
        grainTools::getPositive(e.dict(), "density");
    }
}


namespace
{
typedef nscd::System::Settings solverSettings;

//- contactSolver: the method, its stopping test and the Newton options
void readContactMethod(const Foam::dictionary& cs, solverSettings& s)
{
    using namespace Foam;
    auto positive = [&cs](const char* key, const scalar value)
    {
        return grainTools::getPositiveOrDefault(cs, key, value);
    };
    using Convergence = nscd::System::Settings::Convergence;
    s.convergence = contactSolverChoice<Convergence>
    (
        cs, "convergence", s.convergence,
        {{"max", Convergence::Max}, {"rms", Convergence::RMS}}
    );
    s.rmsTolerance = positive("rmsTolerance", s.rmsTolerance);
    using FrictionLaw = nscd::System::Settings::FrictionLaw;
    s.frictionLaw = contactSolverChoice<FrictionLaw>
    (
        cs, "frictionLaw", s.frictionLaw,
        {{"coulomb", FrictionLaw::Coulomb}, {"anitescu", FrictionLaw::Anitescu}}
    );
    using Method = nscd::System::Settings::Method;
    s.method = contactSolverChoice<Method>
    (
        cs, "method", s.method,
        {
            {"NLGS", Method::NLGS},
            {"overRelaxedNLGS", Method::OverRelaxedNLGS},
            {"APGD", Method::APGD},
            {"NNCG", Method::NNCG},
            {"newton", Method::Newton}
        }
    );
    s.newtonTolerance = positive("newtonTolerance", s.newtonTolerance);
    s.tangentialRegularisation =
        positive("tangentialRegularisation", s.tangentialRegularisation);
    using Linear = nscd::System::Settings::NewtonLinearSolver;
    s.newtonLinearSolver = contactSolverChoice<Linear>
    (
        cs, "newtonLinearSolver", s.newtonLinearSolver,
        {
            {"cholesky", Linear::Cholesky},
            {"conjugateGradient", Linear::ConjugateGradient}
        }
    );
}


//- contactSolver method newton: FatalIOError unless every material of
//  grainDict (constant/grainProperties) has a compliance
void checkNewtonCompliance
(
    const Foam::dictionary& grainDict,
    const Foam::dictionary& cs,
    const solverSettings& s
)
{
    using namespace Foam;
    if (s.method == nscd::System::Settings::Method::Newton)
    {
        // the Newton solver solves the compliant (regularised) law
        // only: every material needs a compliance
        for (const entry& e : grainDict.subDict("materials"))
        {
            if
            (
                !(e.dict().getOrDefault<scalar>("compliance", 0) > 0)
             && !(
                    e.dict().getOrDefault<scalar>("relativeCompliance", 0)
                  > 0
                )
            )
            {
                FatalIOErrorInFunction(cs)
                    << "contactSolver method newton in " << grainDict.name()
                    << " solves compliant contacts only, but material "
                    << e.keyword() << " has neither compliance nor"
                    << " relativeCompliance > 0 (the hard law)." << nl
                    << "    Give materials." << e.keyword()
                    << ".relativeCompliance (e.g. 2e-3) or compliance"
                    << " [m/N], or use method NLGS" << exit(FatalIOError);
            }
        }
    }
}


//- contactSolver: ordering, relaxation, tolerances, iteration and
//  sub-step limits, reordering and the Verlet skin
void readContactLimits(const Foam::dictionary& cs, solverSettings& s)
{
    using namespace Foam;
    using Ordering = nscd::System::Settings::Ordering;
    s.ordering = contactSolverChoice<Ordering>
    (
        cs, "ordering", s.ordering,
        {{"fifo", Ordering::Fifo}, {"symmetric", Ordering::Symmetric}}
    );
    s.relaxation = cs.getOrDefault<scalar>("relaxation", s.relaxation);
    if (!(s.relaxation > 0 && s.relaxation < 2))
    {
        FatalIOErrorInFunction(cs)
            << "relaxation must be in (0, 2), got " << s.relaxation
            << exit(FatalIOError);
    }
    s.tolerance =
        grainTools::getPositiveOrDefault(cs, "tolerance", s.tolerance);
    s.maxIterations =
        cs.getOrDefault<label>("maxIterations", s.maxIterations);
    s.overlapTolerance =
        grainTools::getPositiveOrDefault
        (
            cs, "overlapTolerance", s.overlapTolerance
        );
    if (s.maxIterations < 1)
    {
        FatalIOErrorInFunction(cs)
            << "maxIterations must be >= 1" << exit(FatalIOError);
    }
    s.maxSubSteps = cs.getOrDefault<label>("maxSubSteps", s.maxSubSteps);
    if (s.maxSubSteps < 1)
    {
        FatalIOErrorInFunction(cs)
            << "maxSubSteps must be >= 1" << exit(FatalIOError);
    }
    const label reorder =
        cs.getOrDefault<label>("reorderInterval", s.reorderInterval);
    if (reorder < 0)
    {
        FatalIOErrorInFunction(cs)
            << "reorderInterval must be >= 0 (steps between two internal"
            << " re-sorts of the grains along the Morton curve; 0: never),"
            << " got " << reorder << exit(FatalIOError);
    }
    s.reorderInterval = int(reorder);
    s.verletSkin = cs.getOrDefault<scalar>("verletSkin", s.verletSkin);
    if (!(s.verletSkin >= 0) || !std::isfinite(s.verletSkin))
    {
        FatalIOErrorInFunction(cs)
            << "verletSkin must be finite and >= 0 (skin of the Verlet"
            << " list of candidate grain pairs, / r_min; 0: the grid scan"
            << " every step), got " << s.verletSkin << exit(FatalIOError);
    }
}


//- contactSolver convergence rms only with the Gauss-Seidel methods,
//  frictionLaw anitescu not with APGD
void checkConvergenceChoice
(
    const Foam::dictionary& cs,
    const solverSettings& s
)
{
    using namespace Foam;
    if
    (
        s.convergence == nscd::System::Settings::Convergence::RMS
     && (s.method == nscd::System::Settings::Method::APGD
      || s.method == nscd::System::Settings::Method::NNCG
      || s.method == nscd::System::Settings::Method::Newton)
    )
    {
        FatalIOErrorInFunction(cs)
            << "convergence rms in " << cs.name() << " is the stopping"
            << " test of the Gauss-Seidel methods (method NLGS or"
            << " overRelaxedNLGS); APGD and NNCG stop on convergence max,"
            << " newton on newtonTolerance" << exit(FatalIOError);
    }
    if
    (
        s.frictionLaw == nscd::System::Settings::FrictionLaw::Anitescu
     && s.method == nscd::System::Settings::Method::APGD
    )
    {
        FatalIOErrorInFunction(cs)
            << "frictionLaw anitescu in " << cs.name() << " is solved by"
            << " method NLGS, overRelaxedNLGS, NNCG or newton; APGD solves"
            << " frictionLaw coulomb" << exit(FatalIOError);
    }
}

} // End anonymous namespace


void Foam::grainCloud::applySolverSettings()
{
    nscd::System::Settings& s = system_->settings();
    if (dict_.found("contactSolver"))
    {
        const dictionary& cs = dict_.subDict("contactSolver");
        grainTools::checkKeywords
        (
            cs,
            {
                "tolerance", "maxIterations", "overlapTolerance", "method",
                "relaxation", "maxSubSteps", "reorderInterval", "verletSkin",
                "ordering", "convergence", "rmsTolerance", "newtonTolerance",
                "tangentialRegularisation", "newtonLinearSolver",
                "frictionLaw"
            }
        );
        readContactMethod(cs, s);
        checkNewtonCompliance(dict_, cs, s);
        readContactLimits(cs, s);
        checkConvergenceChoice(cs, s);
    }
}


std::vector<nscd::Material> Foam::grainCloud::dictionaryMaterials() const
{
    std::vector<nscd::Material> list;
    for (const entry& e : dict_.subDict("materials"))
    {
        const dictionary& d = e.dict();
        nscd::Material m;
        m.density = d.get<scalar>("density");
        m.friction = d.get<scalar>("friction");
        m.youngModulus = d.getOrDefault<scalar>("youngModulus", 0);
        m.poissonRatio = d.getOrDefault<scalar>("poissonRatio", 0);
        m.conductivity = d.getOrDefault<scalar>("conductivity", 0);
        m.heatCapacity = d.getOrDefault<scalar>("heatCapacity", 0);
        m.compliance = d.getOrDefault<scalar>("compliance", 0);
        m.relativeCompliance = d.getOrDefault<scalar>("relativeCompliance", 0);
        if (m.conductivity > 0 && !(m.youngModulus > 0))
        {
            WarningInFunction
                << "Material " << e.keyword() << " in " << dict_.name()
                << " has conductivity " << m.conductivity << " but no"
                << " youngModulus: contact conduction (thesis eq. 4.2) is"
                << " off for it, the grains exchange heat with the fluid"
                << " only. Give youngModulus (and poissonRatio) to switch"
                << " it on." << endl;
        }
        list.push_back(m);
    }
    return list;
}


void Foam::grainCloud::applyDictionaryMaterials(const fileName& statePath)
{
    // constant/grainProperties is authoritative, as any constant/ property
    // of an OpenFOAM case: a state written by another case (e.g. a deposit
    // copied into each case that starts from it) keeps its grains but takes
    // this case's materials.  Unchanged materials leave a restart exact.
    const std::vector<nscd::Material> list = dictionaryMaterials();
    const dictionary& mats = dict_.subDict("materials");
    if (label(list.size()) != system_->nMaterials())
    {
        FatalIOErrorInFunction(mats)
            << statePath << " holds " << system_->nMaterials()
            << " materials but " << mats.name() << " lists " << list.size()
            << "." << nl << "    Materials are matched by their order"
            << " (id 0, 1, ...): list as many as the state was written with,"
            << " in the same order, or re-run grainDeposit."
            << exit(FatalIOError);
    }
    wordList names(mats.toc());
    for (label id = 0; id < label(list.size()); ++id)
    {
        const nscd::Material& old = system_->material(id);
        const nscd::Material& m = list[id];
        OStringStream changes;
        auto note = [&changes](const char* what, scalar was, scalar now)
        {
            if (was != now)
            {
                changes << ", " << what << " " << was << " -> " << now;
            }
        };
        note("density", old.density, m.density);
        note("friction", old.friction, m.friction);
        note("youngModulus", old.youngModulus, m.youngModulus);
        note("poissonRatio", old.poissonRatio, m.poissonRatio);
        note("conductivity", old.conductivity, m.conductivity);
        note("heatCapacity", old.heatCapacity, m.heatCapacity);
        note("compliance", old.compliance, m.compliance);
        note
        (
            "relativeCompliance",
            old.relativeCompliance,
            m.relativeCompliance
        );
        if (changes.str().empty())
        {
            continue;
        }
        Info<< "grainCloud: material " << names[id] << " (id " << id
            << ") of constant/grainProperties replaces the one in "
            << (statePath.path().name()/statePath.name()).c_str() << ": "
            << changes.str().substr(2).c_str()
            << " (grain masses recomputed)"
            << endl;
        system_->setMaterial(id, m);
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::label Foam::grainCloud::materialId(const word& name) const
{
    const dictionary& mats = dict_.subDict("materials");
    const wordList names(mats.toc());
    label id = 0;
    for (const entry& e : mats)
    {
        if (e.keyword() == name)
        {
            return id;
        }
        ++id;
    }
    FatalIOErrorInFunction(mats)
        << "Unknown material '" << name << "'. Materials defined in "
        << mats.name() << ": " << flatOutput(names) << exit(FatalIOError);
    return -1;
}

// ************************************************************************* //
