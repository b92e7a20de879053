# Scalable avatars: animation-aware mesh reduction of faces with morph targets.
list(APPEND classes vtkAnimationAwareDecimation)
