// SPDX-License-Identifier: GPL-3.0-or-later
#include "grainDictionaryTools.H"
#include "IOstreams.H"
#include "FlatOutput.H"
#include "wordRes.H"
#include "IFstream.H"

#include <cmath>


void Foam::grainTools::checkUniqueKeywords(const IOdictionary& dict)
{
    const fileName file(dict.filePath());
    if (file.empty())
    {
        return;
    }
    const entry::inputMode mode = entry::globalInputMode;
    const bool throwing = FatalIOError.throwExceptions();
    string what;
    label line = -1;
    try
    {
        IFstream is(file);
        dictionary again(file);
        // dictionary(Istream&) would reset the mode to merge
        entry::globalInputMode = entry::inputMode::ERROR;
        again.read(is);
    }
    catch (const IOerror& err)
    {
        // the file was read before: a duplicated keyword is the only error
        what = err.message();
        line = err.ioStartLineNumber();
    }
    entry::globalInputMode = mode;
    FatalIOError.throwExceptions(throwing);
    if (!what.empty())
    {
        FatalIOError
        (
            FUNCTION_NAME, __FILE__, __LINE__, file, line
        )   << "In " << file << " at line " << line << ": " << what.c_str()
            << " (a keyword given twice in one dictionary: OpenFOAM merges"
            << " the two entries, the later values winning)." << nl
            << "    Fix: give every entry of a dictionary (e.g. every"
            << " material) its own name, or remove the repeated one."
            << exit(FatalIOError);
    }
}

void Foam::grainTools::checkKeywords
(
    const dictionary& dict,
    const wordList& allowed
)
{
    checkKeywords(dict, allowed, wordList());
}


void Foam::grainTools::checkKeywords
(
    const dictionary& dict,
    const wordList& allowed,
    const wordList& generic
)
{
    for (const entry& e : dict)
    {
        if (!allowed.found(e.keyword()) && !generic.found(e.keyword()))
        {
            Ostream& os = FatalIOErrorInFunction(dict)
                << "Unknown keyword '" << e.keyword() << "' in dictionary "
                << dict.name() << nl
                << "    Allowed keywords: " << flatOutput(allowed);
            if (generic.size())
            {
                os  << " and the generic " << flatOutput(generic);
            }
            os  << nl << "    Fix: correct the spelling or remove the entry."
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


Foam::labelList Foam::grainTools::patchIds
(
    const polyBoundaryMesh& pbm,
    const dictionary& dict,
    const word& key,
    const string& consequence
)
{
    const wordRes names(dict.get<wordRes>(key));
    for (const wordRe& name : names)
    {
        bool matched = false;
        for (const word& pn : pbm.names())
        {
            matched = matched || name.match(pn);
        }
        if (!matched)
        {
            FatalIOErrorInFunction(dict)
                << key << " entry '" << name << "' in " << dict.name()
                << " matches no patch of the mesh"
                << (consequence.size() ? " (" + consequence + ")" : string())
                << "." << nl << "    Patches: " << flatOutput(pbm.names())
                << nl << "    Fix: correct the name in " << key << "."
                << exit(FatalIOError);
        }
    }
    return pbm.patchSet(names).sortedToc();
}


Foam::HashTable<Foam::scalar> Foam::grainTools::patchValues
(
    const dictionary& dict,
    const wordList& patches,
    const string& what,
    scalar minValue
)
{
    const word key(dict.dictName());
    HashTable<scalar> values;
    for (const entry& e : dict)
    {
        if (!e.isStream())
        {
            FatalIOErrorInFunction(dict)
                << key << " entry '" << e.keyword() << "' in " << dict.name()
                << " must be '<patch or \"regex\"> <" << what.c_str() << ">;'"
                << exit(FatalIOError);
        }
        const scalar v = dict.get<scalar>(e.keyword());
        if (!std::isfinite(v) || v < minValue)
        {
            FatalIOErrorInFunction(dict)
                << key << " " << e.keyword() << " " << v << " in "
                << dict.name() << ": the " << what.c_str() << " must be a"
                << " finite value >= " << minValue << exit(FatalIOError);
        }
        const wordRe re(e.keyword());
        bool matched = false;
        for (const word& p : patches)
        {
            if (re.match(p))
            {
                values.set(p, v);
                matched = true;
            }
        }
        if (!matched)
        {
            FatalIOErrorInFunction(dict)
                << key << " entry '" << e.keyword() << "' in " << dict.name()
                << " matches no wall patch. Wall patches: "
                << flatOutput(patches) << exit(FatalIOError);
        }
    }
    return values;
}
