// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: stepDataFile (stepDataFile.H)
\*---------------------------------------------------------------------------*/

#include "stepDataFile.H"
#include "Time.H"
#include "writeCheck.H"

#include <cmath>
#include <cstdint>

// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::stepDataFile::stepDataFile
(
    const objectRegistry& obr,
    const word& name,
    const string& title,
    const List<column>& columns
)
:
    functionObjects::writeFile(obr, name, name),
    nColumns_(columns.size())
{
    // 17 significant digits (scientific: 16 after the point)
    writePrecision_ = 16;
    writeToFile_ = Pstream::master();
    if (!writeToFile_)
    {
        return;
    }
    filePtr_ = createFile(name);
    OFstream& os = file();
    checkStreamWrite(os, os.name());
    // each line flushed and checked before the next one's output, which
    // OpenFOAM's stream checks would stop with a bare "error in IOstream"
    auto header = [&](const std::string& line)
    {
        writeHeader(os, line);
        os.flush();
        checkStreamWrite(os, os.name());
    };
    header(std::string(name) + ": " + title);
    header("Time [s]: the time step's end time");
    for (const column& c : columns)
    {
        header(std::string(c.name) + " [" + c.unit + "]: " + c.description);
    }
    writeCommented(os, "Time");
    for (const column& c : columns)
    {
        writeTabbed(os, c.name);
    }
    os  << endl;
    checkStreamWrite(os, os.name());
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::stepDataFile::checkCount(const UList<scalar>& values) const
{
    if (values.size() != nColumns_)
    {
        FatalErrorInFunction
            << fileName_ << ": " << values.size() << " values for "
            << nColumns_ << " columns" << exit(FatalError);
    }
}


void Foam::stepDataFile::writeValues(OFstream& os, const UList<scalar>& values)
{
    for (const scalar v : values)
    {
        os  << tab << setw(charWidth());
        if (std::isfinite(v) && v == std::round(v) && mag(v) < 1e15)
        {
            os  << std::int64_t(v);
        }
        else
        {
            os  << v;
        }
    }
    os  << endl;
    checkStreamWrite(os, os.name());
}


void Foam::stepDataFile::write(const UList<scalar>& values)
{
    checkCount(values);
    if (writeToFile_)
    {
        writeCurrentTime(file());
        writeValues(file(), values);
    }
}


void Foam::stepDataFile::write(const scalar time, const UList<scalar>& values)
{
    checkCount(values);
    if (writeToFile_)
    {
        file() << setw(charWidth()) << time;
        writeValues(file(), values);
    }
}


// ************************************************************************* //
