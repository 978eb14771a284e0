#include "grainDictionaryTools.H"
#include "IOstreams.H"
#include "FlatOutput.H"

void Foam::grainTools::checkKeywords
(
    const dictionary& dict,
    const wordList& allowed
)
{
    for (const entry& e : dict)
    {
        if (!allowed.found(e.keyword()))
        {
            FatalIOErrorInFunction(dict)
                << "Unknown keyword '" << e.keyword() << "' in dictionary "
                << dict.name() << nl
                << "    Allowed keywords: " << flatOutput(allowed) << nl
                << "    Fix: correct the spelling or remove the entry."
                << exit(FatalIOError);
        }
    }
}


Foam::scalar Foam::grainTools::getPositive
(
    const dictionary& dict,
    const word& key
)
{
    const scalar v = dict.get<scalar>(key);
    if (!(v > 0))
    {
        FatalIOErrorInFunction(dict)
            << "Keyword '" << key << "' in " << dict.name()
            << " must be strictly positive, got " << v << nl
            << exit(FatalIOError);
    }
    return v;
}


Foam::scalar Foam::grainTools::getPositiveOrDefault
(
    const dictionary& dict,
    const word& key,
    scalar deflt
)
{
    if (!dict.found(key))
    {
        return deflt;
    }
    return getPositive(dict, key);
}
