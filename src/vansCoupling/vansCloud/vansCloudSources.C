// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud coupling sources (see grainCouplingSource.H)

Description
    The list of grainCouplingSources of the cloud and the calls of their
    hooks: volume source (pEqn.H, psiEqn.H), advance and grain forces after
    setFluidForces.  The grain heat is collected in setHeatSources
    (vansCloud.C), afterGrainStep in evolve (vansCloudForces.C).
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "fvOptionList.H"

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::addCouplingSource(grainCouplingSource& source)
{
    for (const grainCouplingSource* s : couplingSources_)
    {
        if (s == &source)
        {
            return;
        }
    }
    const string why(source.replicatedGrainsReason());
    if (grains_.decomposed() && !why.empty())
    {
        FatalErrorInFunction
            << "The coupling source " << source.couplingName() << " needs"
            << " every grain on every rank: " << why.c_str() << "." << nl
            << "    Fix: grainDecomposition replicated; in"
            << " constant/grainProperties (or change that setting)."
            << exit(FatalError);
    }
    source.attach(*this);
    couplingSources_.append(&source);
    Info<< "vansCloud: coupling source " << source.couplingName() << endl;
}


Foam::label Foam::vansCloud::addCouplingSources(fv::optionList& options)
{
    label n = 0;
    forAll(options, i)
    {
        grainCouplingSource* s =
            dynamic_cast<grainCouplingSource*>(&options[i]);
        if (s)
        {
            addCouplingSource(*s);
            ++n;
        }
    }
    return n;
}


const Foam::volScalarField::Internal*
Foam::vansCloud::couplingVolumeSource() const
{
    const volScalarField::Internal* q = nullptr;
    for (const grainCouplingSource* s : couplingSources_)
    {
        const volScalarField::Internal* qs = s->volumeSource();
        if (qs && q)
        {
            FatalErrorInFunction
                << "Two coupling sources carry a volume source of the"
                << " mixture continuity (the second: " << s->couplingName()
                << "): not supported." << nl
                << "    Fix: keep one blowing source (e.g. one droplet with"
                << " blowing yes)." << exit(FatalError);
        }
        if (qs)
        {
            q = qs;
        }
    }
    return q;
}


void Foam::vansCloud::advanceCouplingSources(const scalar dt)
{
    if (couplingSources_.empty())
    {
        return;
    }
    List<vector> F;
    for (grainCouplingSource* s : couplingSources_)
    {
        s->beforeGrainStep(dt);
    }
    for (const grainCouplingSource* s : couplingSources_)
    {
        s->addGrainForces(F);
    }
    addExternalForces(F);
}


// ************************************************************************* //
