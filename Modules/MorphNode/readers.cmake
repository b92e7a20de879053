# Readers of faces with morph targets.
list(APPEND classes vtkMorphTargetReader)
