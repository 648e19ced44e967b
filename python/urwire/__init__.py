"""urwire: decode and encode the Universal Robots primary/secondary client interface.

    import urwire
    for record in urwire.decode_file("session.pcapng"):   # or a raw stream
        print(urwire.to_json_line(record))

Stream in chunks with `urwire.Framer`; decode one framed message with `urwire.decode_message`;
print canonical JSON with `urwire.to_json_line`.

The modules here are hand-written; `urwire.generated` (messages, enums, spec) is written from
the spec by `make generate`. In the source tree it lives under generated/python/urwire/, which
extend_path adds to this package's path when both python/ and generated/python/ are on sys.path.
"""
import os
from pkgutil import extend_path

# Other folders named urwire on sys.path join this package: in the tree, generated/python/urwire,
# which holds the subpackage `generated` and no __init__.py. A folder with an __init__.py of its
# own is another install of urwire and stays out, so that none of its modules is imported here.
_OWN = list(__path__)
__path__ = [p for p in extend_path(__path__, __name__)
            if p in _OWN or not os.path.isfile(os.path.join(p, "__init__.py"))]

from ._runtime import (DecodeError, EncodeError, GlobalValue, MalformedPackage, MalformedSubtype,  # noqa: E402
                       StreamError, UnknownMessage, UnknownPackage, UnknownSubtype)
from .arguments import parse_version  # noqa: E402
from .canonical import to_dict, to_json_line  # noqa: E402
from .generated.enums import *  # noqa: F401,F403,E402  (every enum of the document)
from .framer import Framer, decode_stream  # noqa: E402
from .generated.messages import *  # noqa: F401,F403,E402  (every message and sub-package class)
from .decoding import decode_message, encode_message, package_classes  # noqa: E402
from .message_kinds import encode_package  # noqa: E402
from .reading import decode_file  # noqa: E402
from .backends import backend  # noqa: E402
from .generated.spec import DEFAULT_VERSION, DOCUMENTED_VERSIONS, PORTS  # noqa: E402

__version__ = "0.1.0"

__all__ = [
    "DecodeError", "EncodeError", "GlobalValue", "MalformedPackage", "MalformedSubtype", "StreamError",
    "UnknownMessage", "UnknownPackage", "UnknownSubtype", "Framer", "decode_stream", "parse_version",
    "decode_file", "decode_message", "encode_message", "package_classes", "to_dict", "to_json_line",
    "DEFAULT_VERSION", "DOCUMENTED_VERSIONS", "PORTS", "backend",
]
