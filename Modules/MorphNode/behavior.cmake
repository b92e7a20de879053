# Behaviour control: the temporal weight source over morphnode::BehaviorController.
list(APPEND classes vtkBehaviorTimeSource)
