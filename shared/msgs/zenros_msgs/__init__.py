"""zenros_msgs: the robot's own types (chassis state and sim services, the PTZ camera's, the
gateway's media folders, tasks and their documents, nav points, the result codes of their
calls).

One module per service that owns them; importing this package registers them all.
"""

from .blockly import *  # noqa: F403
from .blockly import __all__ as _blockly_all
from .chassis import *  # noqa: F403
from .chassis import __all__ as _chassis_all
from .config import *  # noqa: F403
from .config import __all__ as _config_all
from .elevator import *  # noqa: F403
from .elevator import __all__ as _elevator_all
from .lifecycle import *  # noqa: F403
from .lifecycle import __all__ as _lifecycle_all
from .media import *  # noqa: F403
from .media import __all__ as _media_all
from .nav import *  # noqa: F403
from .nav import __all__ as _nav_all
from .people import *  # noqa: F403
from .people import __all__ as _people_all
from .ptz import *  # noqa: F403
from .ptz import __all__ as _ptz_all
from .result import *  # noqa: F403
from .result import __all__ as _result_all
from .schedule import *  # noqa: F403
from .schedule import __all__ as _schedule_all
from .slam import *  # noqa: F403
from .slam import __all__ as _slam_all
from .task_actions import *  # noqa: F403
from .task_actions import __all__ as _task_actions_all
from .task_docs import *  # noqa: F403
from .task_docs import __all__ as _task_docs_all
from .tasks import *  # noqa: F403
from .tasks import __all__ as _tasks_all
from .traffic import *  # noqa: F403
from .traffic import __all__ as _traffic_all

__all__ = [*_blockly_all, *_chassis_all, *_config_all, *_elevator_all, *_lifecycle_all,
           *_media_all, *_nav_all, *_people_all, *_ptz_all, *_result_all, *_schedule_all, *_slam_all,
           *_task_actions_all, *_task_docs_all, *_tasks_all, *_traffic_all]
