"""``python -m zenros.launch FILE [name:=value ...]``, the same as ``zenros launch``."""

from .cli import main
from .zenoh_hooks import ZenohLaunch

raise SystemExit(main(hooks=ZenohLaunch().hooks()))
