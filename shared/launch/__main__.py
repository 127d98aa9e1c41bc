"""``python -m zenros.launch FILE [name:=value ...]``, the same as ``zenros launch``."""

from .cli import main

raise SystemExit(main())
