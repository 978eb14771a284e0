// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::GrainColumns: the registry of named per-grain columns (GrainColumns.H).
#include "nscd/GrainColumns.H"

namespace nscd
{

const char* columnTypeName(ColumnType t)
{
    switch (t)
    {
    case ColumnType::Double:
        return "double";
    case ColumnType::Vec3:
        return "Vec3";
    case ColumnType::Quaternion:
        return "quaternion";
    case ColumnType::Int:
        return "int";
    case ColumnType::Long:
        return "long";
    case ColumnType::Char:
        return "char";
    }
    return "?";
}

GrainColumns& GrainColumns::operator=(const GrainColumns& o)
{
    if (this == &o) return *this;
    for (int k = 0; k < o.count(); ++k)
    {
        const int mine = find(o[k].name());
        if (mine >= 0)
            columns_[mine]->assign(o[k]);
        else
            columns_.push_back(o[k].clone());
    }
    return *this;
}

int GrainColumns::find(const std::string& name) const
{
    for (std::size_t k = 0; k < columns_.size(); ++k)
        if (columns_[k]->name() == name) return int(k);
    return -1;
}

std::size_t GrainColumns::rowBytes(unsigned flags) const
{
    std::size_t n = 0;
    for (const auto& c : columns_)
        if (c->has(flags)) n += c->elementBytes();
    return n;
}

void GrainColumns::packRow(std::size_t i, unsigned flags, char* out) const
{
    for (const auto& c : columns_)
        if (c->has(flags))
        {
            c->pack(i, out);
            out += c->elementBytes();
        }
}

void GrainColumns::unpackRow(std::size_t i, unsigned flags, const char* in)
{
    for (auto& c : columns_)
        if (c->has(flags))
        {
            c->unpack(i, in);
            in += c->elementBytes();
        }
}

} // namespace nscd
