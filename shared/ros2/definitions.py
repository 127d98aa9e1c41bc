"""ROS 2 interface definitions of the standard types zenros carries, in .msg syntax.

These restate the public ROS 2 interfaces (field types, names and order: the wire layout and
what the RIHS01 hash covers; constants and defaults are left out). The tests check each one
against the ROS 2 interface wheels (parsed fields and type hashes); tf2_msgs and
example_interfaces have no wheel here and are checked by hand only.
"""

from __future__ import annotations

from .common_definitions import COMMON_ACTIONS, COMMON_MESSAGES, COMMON_SERVICES
from .nav2_definitions import NAV2_ACTIONS, NAV2_MESSAGES, NAV2_SERVICES

__all__ = ["ACTIONS", "MESSAGES", "SERVICES"]

MESSAGES: dict[str, str] = {
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec",
    "builtin_interfaces/msg/Duration": "int32 sec\nuint32 nanosec",
    "std_msgs/msg/Header": "builtin_interfaces/Time stamp\nstring frame_id",
    "std_msgs/msg/Empty": "",
    "std_msgs/msg/String": "string data",
    "std_msgs/msg/Bool": "bool data",
    "std_msgs/msg/Int32": "int32 data",
    "std_msgs/msg/Int64": "int64 data",
    "std_msgs/msg/UInt8": "uint8 data",
    "std_msgs/msg/Float32": "float32 data",
    "std_msgs/msg/Float64": "float64 data",
    "std_msgs/msg/ColorRGBA": "float32 r\nfloat32 g\nfloat32 b\nfloat32 a",
    "geometry_msgs/msg/Vector3": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/msg/Vector3Stamped": "std_msgs/Header header\nVector3 vector",
    "geometry_msgs/msg/Point": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/msg/Point32": "float32 x\nfloat32 y\nfloat32 z",
    "geometry_msgs/msg/PointStamped": "std_msgs/Header header\nPoint point",
    "geometry_msgs/msg/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w",
    "geometry_msgs/msg/QuaternionStamped": "std_msgs/Header header\nQuaternion quaternion",
    "geometry_msgs/msg/Pose": "Point position\nQuaternion orientation",
    "geometry_msgs/msg/Pose2D": "float64 x\nfloat64 y\nfloat64 theta",
    "geometry_msgs/msg/PoseStamped": "std_msgs/Header header\nPose pose",
    "geometry_msgs/msg/PoseWithCovariance": "Pose pose\nfloat64[36] covariance",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "std_msgs/Header header\nPoseWithCovariance pose",
    "geometry_msgs/msg/PoseArray": "std_msgs/Header header\nPose[] poses",
    "geometry_msgs/msg/Transform": "Vector3 translation\nQuaternion rotation",
    "geometry_msgs/msg/TransformStamped":
        "std_msgs/Header header\nstring child_frame_id\nTransform transform",
    "geometry_msgs/msg/Twist": "Vector3 linear\nVector3 angular",
    "geometry_msgs/msg/TwistStamped": "std_msgs/Header header\nTwist twist",
    "geometry_msgs/msg/TwistWithCovariance": "Twist twist\nfloat64[36] covariance",
    "geometry_msgs/msg/TwistWithCovarianceStamped":
        "std_msgs/Header header\nTwistWithCovariance twist",
    "geometry_msgs/msg/Polygon": "Point32[] points",
    "geometry_msgs/msg/PolygonStamped": "std_msgs/Header header\nPolygon polygon",
    "sensor_msgs/msg/LaserScan": """
        std_msgs/Header header
        float32 angle_min
        float32 angle_max
        float32 angle_increment
        float32 time_increment
        float32 scan_time
        float32 range_min
        float32 range_max
        float32[] ranges
        float32[] intensities""",
    "sensor_msgs/msg/BatteryState": """
        std_msgs/Header header
        float32 voltage
        float32 temperature
        float32 current
        float32 charge
        float32 capacity
        float32 design_capacity
        float32 percentage
        uint8 power_supply_status
        uint8 power_supply_health
        uint8 power_supply_technology
        bool present
        float32[] cell_voltage
        float32[] cell_temperature
        string location
        string serial_number""",
    "sensor_msgs/msg/Imu": """
        std_msgs/Header header
        geometry_msgs/Quaternion orientation
        float64[9] orientation_covariance
        geometry_msgs/Vector3 angular_velocity
        float64[9] angular_velocity_covariance
        geometry_msgs/Vector3 linear_acceleration
        float64[9] linear_acceleration_covariance""",
    "sensor_msgs/msg/JointState": """
        std_msgs/Header header
        string[] name
        float64[] position
        float64[] velocity
        float64[] effort""",
    "nav_msgs/msg/Odometry": """
        std_msgs/Header header
        string child_frame_id
        geometry_msgs/PoseWithCovariance pose
        geometry_msgs/TwistWithCovariance twist""",
    "nav_msgs/msg/MapMetaData": """
        builtin_interfaces/Time map_load_time
        float32 resolution
        uint32 width
        uint32 height
        geometry_msgs/Pose origin""",
    "nav_msgs/msg/OccupancyGrid": "std_msgs/Header header\nMapMetaData info\nint8[] data",
    "nav_msgs/msg/Path": "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses",
    "rcl_interfaces/msg/Log": """
        builtin_interfaces/Time stamp
        uint8 level
        string name
        string msg
        string file
        string function
        uint32 line""",
    "rcl_interfaces/msg/ParameterType": "",
    "rcl_interfaces/msg/ParameterValue": """
        uint8 type
        bool bool_value
        int64 integer_value
        float64 double_value
        string string_value
        byte[] byte_array_value
        bool[] bool_array_value
        int64[] integer_array_value
        float64[] double_array_value
        string[] string_array_value""",
    "rcl_interfaces/msg/Parameter": "string name\nParameterValue value",
    "rcl_interfaces/msg/ParameterEvent": """
        builtin_interfaces/Time stamp
        string node
        Parameter[] new_parameters
        Parameter[] changed_parameters
        Parameter[] deleted_parameters""",
    "rcl_interfaces/msg/FloatingPointRange": "float64 from_value\nfloat64 to_value\nfloat64 step",
    "rcl_interfaces/msg/IntegerRange": "int64 from_value\nint64 to_value\nuint64 step",
    "rcl_interfaces/msg/ParameterDescriptor": """
        string name
        uint8 type
        string description
        string additional_constraints
        bool read_only
        bool dynamic_typing
        FloatingPointRange[<=1] floating_point_range
        IntegerRange[<=1] integer_range""",
    "rcl_interfaces/msg/SetParametersResult": "bool successful\nstring reason",
    "rcl_interfaces/msg/ListParametersResult": "string[] names\nstring[] prefixes",
    # ros/bond_core's bond/msg/Status (no wheel here: checked by hand)
    "bond/msg/Status": """
        std_msgs/Header header
        string id
        string instance_id
        bool active
        float32 heartbeat_timeout
        float32 heartbeat_period""",
    "lifecycle_msgs/msg/State": "uint8 id\nstring label",
    "lifecycle_msgs/msg/Transition": "uint8 id\nstring label",
    "lifecycle_msgs/msg/TransitionDescription":
        "Transition transition\nState start_state\nState goal_state",
    "lifecycle_msgs/msg/TransitionEvent":
        "uint64 timestamp\nTransition transition\nState start_state\nState goal_state",
    "rosgraph_msgs/msg/Clock": "builtin_interfaces/Time clock",
    "tf2_msgs/msg/TFMessage": "geometry_msgs/TransformStamped[] transforms",
    "tf2_msgs/msg/TF2Error": "uint8 error\nstring error_string",
    "diagnostic_msgs/msg/KeyValue": "string key\nstring value",
    "diagnostic_msgs/msg/DiagnosticStatus": """
        byte level
        string name
        string message
        string hardware_id
        KeyValue[] values""",
    "diagnostic_msgs/msg/DiagnosticArray": "std_msgs/Header header\nDiagnosticStatus[] status",
    # the parts ROS 2 adds around every service and action
    "service_msgs/msg/ServiceEventInfo": """
        uint8 event_type
        builtin_interfaces/Time stamp
        char[16] client_gid
        int64 sequence_number""",
    "unique_identifier_msgs/msg/UUID": "uint8[16] uuid",
    "action_msgs/msg/GoalInfo": "unique_identifier_msgs/UUID goal_id\nbuiltin_interfaces/Time stamp",
    "action_msgs/msg/GoalStatus": "GoalInfo goal_info\nint8 status",
    "action_msgs/msg/GoalStatusArray": "GoalStatus[] status_list",
}

MESSAGES.update({
    "type_description_interfaces/msg/FieldType":
        "uint8 type_id\nuint64 capacity\nuint64 string_capacity\nstring<=255 nested_type_name",
    "type_description_interfaces/msg/Field": "string name\nFieldType type\nstring default_value",
    "type_description_interfaces/msg/IndividualTypeDescription":
        "string<=255 type_name\nField[] fields",
    "type_description_interfaces/msg/TypeDescription":
        "IndividualTypeDescription type_description\n"
        "IndividualTypeDescription[] referenced_type_descriptions",
    "type_description_interfaces/msg/TypeSource":
        "string type_name\nstring encoding\nstring raw_file_contents",
    "type_description_interfaces/msg/KeyValue": "string key\nstring value",
})

SERVICES: dict[str, str] = {
    "type_description_interfaces/srv/GetTypeDescription":
        "string type_name\nstring type_hash\nbool include_type_sources\n---\n"
        "bool successful\nstring failure_reason\nTypeDescription type_description\n"
        "TypeSource[] type_sources\nKeyValue[] extra_information",
    "std_srvs/srv/Empty": "---",
    "std_srvs/srv/Trigger": "---\nbool success\nstring message",
    "std_srvs/srv/SetBool": "bool data\n---\nbool success\nstring message",
    "lifecycle_msgs/srv/ChangeState": "Transition transition\n---\nbool success",
    "lifecycle_msgs/srv/GetState": "---\nState current_state",
    "lifecycle_msgs/srv/GetAvailableStates": "---\nState[] available_states",
    "lifecycle_msgs/srv/GetAvailableTransitions":
        "---\nTransitionDescription[] available_transitions",
    "diagnostic_msgs/srv/SelfTest": "---\nstring id\nbyte passed\nDiagnosticStatus[] status",
    "diagnostic_msgs/srv/AddDiagnostics":
        "string load_namespace\n---\nbool success\nstring message",
    "example_interfaces/srv/AddTwoInts": "int64 a\nint64 b\n---\nint64 sum",
    "rcl_interfaces/srv/ListParameters":
        "string[] prefixes\nuint64 depth\n---\nListParametersResult result",
    "rcl_interfaces/srv/DescribeParameters": "string[] names\n---\nParameterDescriptor[] descriptors",
    "rcl_interfaces/srv/GetParameterTypes": "string[] names\n---\nuint8[] types",
    "rcl_interfaces/srv/GetParameters": "string[] names\n---\nParameterValue[] values",
    "rcl_interfaces/srv/SetParameters": "Parameter[] parameters\n---\nSetParametersResult[] results",
    "rcl_interfaces/srv/SetParametersAtomically":
        "Parameter[] parameters\n---\nSetParametersResult result",
    "action_msgs/srv/CancelGoal": "GoalInfo goal_info\n---\nint8 return_code\nGoalInfo[] goals_canceling",
}

ACTIONS: dict[str, str] = {
    "example_interfaces/action/Fibonacci": "int32 order\n---\nint32[] sequence\n---\nint32[] sequence",
    # the action the ROS 2 wheels ship (rclpy's tests use it); zenros.msgs.test_msgs has its classes
    "test_msgs/action/Fibonacci": "int32 order\n---\nint32[] sequence\n---\nint32[] sequence",
    # the ROS 2 action tutorials' (roslibjs's ROS 2 examples); zenros.msgs.action_tutorials_interfaces
    "action_tutorials_interfaces/action/Fibonacci":
        "int32 order\n---\nint32[] sequence\n---\nint32[] partial_sequence",
}

# nav2_msgs: Nav2's own field lists (nav2_definitions.py), so their hashes are Nav2's
MESSAGES.update(NAV2_MESSAGES)
SERVICES.update(NAV2_SERVICES)
ACTIONS.update(NAV2_ACTIONS)

# the rest of common_interfaces and test_msgs (common_definitions.py)
MESSAGES.update(COMMON_MESSAGES)
SERVICES.update(COMMON_SERVICES)
ACTIONS.update(COMMON_ACTIONS)
