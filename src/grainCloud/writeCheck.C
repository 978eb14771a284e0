// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: writeCheck (writeCheck.H)
\*---------------------------------------------------------------------------*/

#include "writeCheck.H"
#include "OSspecific.H"
#include "PstreamReduceOps.H"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sys/stat.h>
#include <sys/statvfs.h>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{

using namespace Foam;

//- Why the file f of a finished write is incomplete, or "" when it is not
std::string incompleteFile(const fileName& f)
{
    struct stat st;
    if (::stat(f.c_str(), &st) != 0)
    {
        return std::string("cannot be read (") + std::strerror(errno) + ")";
    }
    if (!S_ISREG(st.st_mode))
    {
        return "is not a regular file";
    }
    if (st.st_size == 0)
    {
        return "is empty";
    }
    std::ifstream is(f.c_str(), std::ios::binary);
    char head[4] = {0, 0, 0, 0};
    is.read(head, 4);
    if (f.hasExt("gz") || std::string(head, 4) != "/*--")
    {
        return "";  // not an OpenFOAM file with the banner (grainState.h5)
    }
    const std::streamoff n = std::min<std::streamoff>(st.st_size, 160);
    std::string tail(n, '\0');
    is.seekg(st.st_size - n);
    is.read(&tail[0], n);
    if (tail.find("******** //") == std::string::npos)
    {
        return "is cut short (no end line '// *** //')";
    }
    return "";
}


//- The first incomplete file under dir (recursive), with why, or ""
std::string firstIncomplete(const fileName& dir)
{
    for (const fileName& f : readDir(dir, fileName::FILE, false, false))
    {
        const std::string why = incompleteFile(dir/f);
        if (!why.empty())
        {
            return std::string(dir/f) + " " + why;
        }
    }
    for (const fileName& d : readDir(dir, fileName::DIRECTORY, false, false))
    {
        const std::string bad = firstIncomplete(dir/d);
        if (!bad.empty())
        {
            return bad;
        }
    }
    return "";
}

} // End anonymous namespace


// * * * * * * * * * * * * * * * Global Functions  * * * * * * * * * * * * * //

std::string Foam::noSpaceHint(const fileName& path)
{
    struct statvfs vfs;
    if (::statvfs(path.c_str(), &vfs) != 0)
    {
        return "";
    }
    const unsigned long long avail =
        static_cast<unsigned long long>(vfs.f_bavail)*vfs.f_frsize;
    if (avail >= 65536)
    {
        return "";
    }
    return
        " (no space left on device: " + std::to_string(avail)
      + " bytes free on its file system)";
}


void Foam::checkTimeWrite(const Time& runTime, const std::string& failure)
{
    const fileName dir(runTime.timePath());
    std::string bad;
    if (!failure.empty())
    {
        bad = failure;
        const std::size_t end = bad.find_last_not_of(" \n");
        bad.erase(end == std::string::npos ? 0 : end + 1);
    }
    else if (!isDir(dir))
    {
        bad = std::string(dir) + " was not created";
    }
    else if (!isFile(dir/"uniform"/"time"))
    {
        bad = std::string(dir/"uniform"/"time") + " is missing";
    }
    else
    {
        bad = firstIncomplete(dir);
    }
    const bool failed = returnReduce(!bad.empty(), orOp<bool>());
    if (!failed)
    {
        return;
    }
    const fileName moved(dir + ".incomplete");
    if (isDir(moved))
    {
        rmDir(moved);
    }
    const bool renamed = isDir(dir) && Foam::mv(dir, moved);
    // parallel: the grain state of this time in the case directory too
    // (else a restart would be refused as starting before it)
    const fileName global(runTime.globalPath()/runTime.timeName());
    if (Pstream::parRun() && Pstream::master() && isDir(global))
    {
        if (isDir(global + ".incomplete"))
        {
            rmDir(global + ".incomplete");
        }
        Foam::mv(global, global + ".incomplete");
    }
    const std::string hint(noSpaceHint(runTime.path()));
    FatalErrorInFunction
        << "Writing the time directory " << runTime.timeName() << " failed"
        << (hint.empty() ? "" : hint.c_str()) << ": "
        << (bad.empty() ? "another rank's write failed" : bad.c_str())
        << "." << nl << "    " << (renamed ? "It was moved to " : "")
        << (renamed ? moved.c_str() : "")
        << (renamed ? "; the" : "The") << " previous write holds the last"
        << " complete state." << nl << "    Fix: "
        << (hint.empty()
            ? "check the disk (space, quota, permissions)"
            : "free disk space")
        << ", then continue with startFrom latestTime." << exit(FatalError);
}


void Foam::checkStreamWrite(OFstream& os, const fileName& file)
{
    if (os.good() && os.stdStream().good())
    {
        return;
    }
    const int code = errno;
    std::string hint(noSpaceHint(file.path()));
    if (hint.empty() && code == ENOSPC)
    {
        hint = " (no space left on device)";
    }
    FatalErrorInFunction
        << "Writing " << file << " failed"
        << (hint.empty() ? "" : hint.c_str()) << "." << nl
        << "    Its earlier rows are kept; the time directories written so"
        << " far hold complete states." << nl << "    Fix: "
        << (hint.empty()
            ? "check the disk (space, quota, permissions)"
            : "free disk space")
        << ", then continue with startFrom latestTime." << exit(FatalError);
}


// ************************************************************************* //
