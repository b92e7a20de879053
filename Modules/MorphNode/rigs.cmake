# Face rigs: semantic shapes (visemes, expressions) over a face's own targets.
list(APPEND classes vtkMorphRigFilter vtkMorphRigBaker)
list(APPEND private_headers vtkMorphRigCache.h)
