# SPDX-License-Identifier: BSD-3-Clause
"""Helpers the Python tests share (the tests run from this folder, so `import
morphnode_testing` finds it)."""
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand


class Errors:
    """Collects the error messages (vtkErrorMacro) an object reports, so that a test checks
    for a clear message instead of letting it print."""

    def __init__(self, obj):
        self.messages = []

        @calldata_type(VTK_STRING)
        def on_error(caller, event, message):
            self.messages.append(message)

        obj.AddObserver(vtkCommand.ErrorEvent, on_error)
