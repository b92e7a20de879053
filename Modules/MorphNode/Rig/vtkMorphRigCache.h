// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphRigCache
 * @brief   the rig file of a rig filter, read once (private to MorphNode)
 *
 * vtkMorphRigFilter and vtkMorphRigBaker read their rig here: again only when the file
 * name changes or the filter was modified after the last read (so `Modified()` after
 * rewriting the file re-reads it), not when an upstream change re-executes the filter.
 */
#ifndef vtkMorphRigCache_h
#define vtkMorphRigCache_h

#include "base/Error.h"
#include "rig/Rig.h"

#include "vtkIndent.h"
#include "vtkTimeStamp.h"

#include <memory>
#include <ostream>
#include <string>

class vtkMorphRigCache
{
public:
  /// The rig of `fileName`; `filterMTime` is the owning filter's own MTime. Throws
  /// morphnode::InputError for an empty name or a file that does not read as a rig.
  morphnode::Rig& Get(const std::string& fileName, vtkMTimeType filterMTime)
  {
    if (fileName.empty())
    {
      throw morphnode::InputError("no rig file: call SetRigFileName()");
    }
    if (!this->Rig || this->FileName != fileName || filterMTime > this->LoadTime.GetMTime())
    {
      this->Rig.reset();
      this->Rig.reset(new morphnode::Rig(morphnode::Rig::LoadFile(fileName)));
      this->FileName = fileName;
      this->LoadTime.Modified();
    }
    return *this->Rig;
  }

  /// The rig of the last successful Get(), or nullptr.
  const morphnode::Rig* GetLoaded() const { return this->Rig.get(); }

  /// For PrintSelf.
  void Print(std::ostream& os, vtkIndent indent) const
  {
    os << indent << "Rig: ";
    if (this->Rig)
    {
      os << this->Rig->GetName() << ", " << this->Rig->GetNumberOfShapes() << " shapes (read from "
         << this->FileName << ")\n";
    }
    else
    {
      os << "(not read)\n";
    }
  }

private:
  std::unique_ptr<morphnode::Rig> Rig; ///< as read, unbound
  std::string FileName;
  vtkTimeStamp LoadTime;
};

#endif
// VTK-HeaderTest-Exclude: vtkMorphRigCache.h
