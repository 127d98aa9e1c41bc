"""ROS 2 definitions of the rest of common_interfaces (std_msgs, geometry_msgs, sensor_msgs,
nav_msgs, shape_msgs, stereo_msgs, trajectory_msgs, visualization_msgs), rcl_interfaces's
logger levels and test_msgs, as the Kilted wheels ship them, comments left out: the types
`zenros interface generate` wrote into `zenros.msgs`. Checked against the wheels as
`definitions` is."""

from __future__ import annotations

__all__ = ["COMMON_ACTIONS", "COMMON_MESSAGES", "COMMON_SERVICES"]

COMMON_MESSAGES: dict[str, str] = {
    "example_interfaces/msg/Bool": "bool data",
    "example_interfaces/msg/Byte": "byte data",
    "example_interfaces/msg/ByteMultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        byte[]            data          # array of data""",
    "example_interfaces/msg/Char": "char data",
    "example_interfaces/msg/Empty": "",
    "example_interfaces/msg/Float32": "float32 data",
    "example_interfaces/msg/Float32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        float32[]         data          # array of data""",
    "example_interfaces/msg/Float64": "float64 data",
    "example_interfaces/msg/Float64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        float64[]         data          # array of data""",
    "example_interfaces/msg/Int16": "int16 data",
    "example_interfaces/msg/Int16MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int16[]           data          # array of data""",
    "example_interfaces/msg/Int32": "int32 data",
    "example_interfaces/msg/Int32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int32[]           data          # array of data""",
    "example_interfaces/msg/Int64": "int64 data",
    "example_interfaces/msg/Int64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int64[]           data          # array of data""",
    "example_interfaces/msg/Int8": "int8 data",
    "example_interfaces/msg/Int8MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int8[]            data          # array of data""",
    "example_interfaces/msg/MultiArrayDimension": """
        string label   # label of given dimension
        uint32 size    # size of given dimension (in type units)
        uint32 stride  # stride of given dimension""",
    "example_interfaces/msg/MultiArrayLayout": """
        MultiArrayDimension[] dim # Array of dimension properties
        uint32 data_offset        # padding bytes at front of data""",
    "example_interfaces/msg/String": "string data",
    "example_interfaces/msg/UInt16": "uint16 data",
    "example_interfaces/msg/UInt16MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint16[]            data        # array of data""",
    "example_interfaces/msg/UInt32": "uint32 data",
    "example_interfaces/msg/UInt32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint32[]          data          # array of data""",
    "example_interfaces/msg/UInt64": "uint64 data",
    "example_interfaces/msg/UInt64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint64[]          data          # array of data""",
    "example_interfaces/msg/UInt8": "uint8 data",
    "example_interfaces/msg/UInt8MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint8[]           data          # array of data""",
    "example_interfaces/msg/WString": "wstring data",
    "geometry_msgs/msg/Accel": """
        Vector3  linear
        Vector3  angular""",
    "geometry_msgs/msg/AccelStamped": """
        std_msgs/Header header
        Accel accel""",
    "geometry_msgs/msg/AccelWithCovariance": """
        Accel accel
        float64[36] covariance""",
    "geometry_msgs/msg/AccelWithCovarianceStamped": """
        std_msgs/Header header
        AccelWithCovariance accel""",
    "geometry_msgs/msg/Inertia": """
        float64 m
        geometry_msgs/Vector3 com
        float64 ixx
        float64 ixy
        float64 ixz
        float64 iyy
        float64 iyz
        float64 izz""",
    "geometry_msgs/msg/InertiaStamped": """
        std_msgs/Header header
        Inertia inertia""",
    "geometry_msgs/msg/PolygonInstance": """
        geometry_msgs/Polygon polygon
        int64 id""",
    "geometry_msgs/msg/PolygonInstanceStamped": """
        std_msgs/Header header
        geometry_msgs/PolygonInstance polygon""",
    "geometry_msgs/msg/VelocityStamped": """
        std_msgs/Header header
        string body_frame_id
        string reference_frame_id
        Twist velocity""",
    "geometry_msgs/msg/Wrench": """
        Vector3  force
        Vector3  torque""",
    "geometry_msgs/msg/WrenchStamped": """
        std_msgs/Header header
        Wrench wrench""",
    "nav_msgs/msg/Goals": """
        std_msgs/Header header
        geometry_msgs/PoseStamped[] goals""",
    "nav_msgs/msg/GridCells": """
        std_msgs/Header header
        float32 cell_width
        float32 cell_height
        geometry_msgs/Point[] cells""",
    "rcl_interfaces/msg/LoggerLevel": """
        uint8 LOG_LEVEL_UNKNOWN = 0
        uint8 LOG_LEVEL_DEBUG = 10
        uint8 LOG_LEVEL_INFO = 20
        uint8 LOG_LEVEL_WARN = 30
        uint8 LOG_LEVEL_ERROR = 40
        uint8 LOG_LEVEL_FATAL = 50
        string name
        uint32 level""",
    "rcl_interfaces/msg/ParameterEventDescriptors": """
        ParameterDescriptor[] new_parameters
        ParameterDescriptor[] changed_parameters
        ParameterDescriptor[] deleted_parameters""",
    "rcl_interfaces/msg/SetLoggerLevelsResult": """
        bool successful
        string reason""",
    "sensor_msgs/msg/CameraInfo": """
        std_msgs/Header header # Header timestamp should be acquisition time of image
        uint32 height
        uint32 width
        string distortion_model
        float64[] d
        float64[9]  k # 3x3 row-major matrix
        float64[9]  r # 3x3 row-major matrix
        float64[12] p # 3x4 row-major matrix
        uint32 binning_x
        uint32 binning_y
        RegionOfInterest roi""",
    "sensor_msgs/msg/ChannelFloat32": """
        string name
        float32[] values""",
    "sensor_msgs/msg/CompressedImage": """
        std_msgs/Header header # Header timestamp should be acquisition time of image
        string format                # Specifies the format of the data
        uint8[] data                 # Compressed image buffer""",
    "sensor_msgs/msg/FluidPressure": """
        std_msgs/Header header # timestamp of the measurement
        float64 fluid_pressure       # Absolute pressure reading in Pascals.
        float64 variance             # 0 is interpreted as variance unknown""",
    "sensor_msgs/msg/Illuminance": """
        std_msgs/Header header # timestamp is the time the illuminance was measured
        float64 illuminance          # Measurement of the Photometric Illuminance in Lux.
        float64 variance             # 0 is interpreted as variance unknown""",
    "sensor_msgs/msg/Image": """
        std_msgs/Header header # Header timestamp should be acquisition time of image
        uint32 height                # image height, that is, number of rows
        uint32 width                 # image width, that is, number of columns
        string encoding       # Encoding of pixels -- channel meaning, ordering, size
        uint8 is_bigendian    # is this data bigendian?
        uint32 step           # Full row length in bytes
        uint8[] data          # actual matrix data, size is (step * rows)""",
    "sensor_msgs/msg/Joy": """
        std_msgs/Header header
        float32[] axes
        int32[] buttons""",
    "sensor_msgs/msg/JoyFeedback": """
        uint8 TYPE_LED    = 0
        uint8 TYPE_RUMBLE = 1
        uint8 TYPE_BUZZER = 2
        uint8 type
        uint8 id
        float32 intensity""",
    "sensor_msgs/msg/JoyFeedbackArray": "JoyFeedback[] array",
    "sensor_msgs/msg/LaserEcho": """
        float32[] echoes  # Multiple values of ranges or intensities.""",
    "sensor_msgs/msg/MagneticField": """
        std_msgs/Header header               # timestamp is the time the
        geometry_msgs/Vector3 magnetic_field # x, y, and z components of the
        float64[9] magnetic_field_covariance       # Row major about x, y, z axes""",
    "sensor_msgs/msg/MultiDOFJointState": """
        std_msgs/Header header
        string[] joint_names
        geometry_msgs/Transform[] transforms
        geometry_msgs/Twist[] twist
        geometry_msgs/Wrench[] wrench""",
    "sensor_msgs/msg/MultiEchoLaserScan": """
        std_msgs/Header header # timestamp in the header is the acquisition time of
        float32 angle_min            # start angle of the scan [rad]
        float32 angle_max            # end angle of the scan [rad]
        float32 angle_increment      # angular distance between measurements [rad]
        float32 time_increment       # time between measurements [seconds] - if your scanner
        float32 scan_time            # time between scans [seconds]
        float32 range_min            # minimum range value [m]
        float32 range_max            # maximum range value [m]
        LaserEcho[] ranges           # range data [m]
        LaserEcho[] intensities      # intensity data [device-specific units].  If your""",
    "sensor_msgs/msg/NavSatFix": """
        std_msgs/Header header
        NavSatStatus status
        float64 latitude
        float64 longitude
        float64 altitude
        float64[9] position_covariance
        uint8 COVARIANCE_TYPE_UNKNOWN = 0
        uint8 COVARIANCE_TYPE_APPROXIMATED = 1
        uint8 COVARIANCE_TYPE_DIAGONAL_KNOWN = 2
        uint8 COVARIANCE_TYPE_KNOWN = 3
        uint8 position_covariance_type""",
    "sensor_msgs/msg/NavSatStatus": """
        int8 STATUS_UNKNOWN = -2        # status is not yet set
        int8 STATUS_NO_FIX =  -1        # unable to fix position
        int8 STATUS_FIX =      0        # unaugmented fix
        int8 STATUS_SBAS_FIX = 1        # with satellite-based augmentation
        int8 STATUS_GBAS_FIX = 2        # with ground-based augmentation
        int8 status -2 # STATUS_UNKNOWN
        uint16 SERVICE_UNKNOWN = 0  # Remember service is a bitfield, so checking (service & SERVICE_UNKNOWN) will not work. Use == instead.
        uint16 SERVICE_GPS =     1
        uint16 SERVICE_GLONASS = 2
        uint16 SERVICE_COMPASS = 4      # includes BeiDou.
        uint16 SERVICE_GALILEO = 8
        uint16 service""",
    "sensor_msgs/msg/PointCloud": """
        std_msgs/Header header
        geometry_msgs/Point32[] points
        ChannelFloat32[] channels""",
    "sensor_msgs/msg/PointCloud2": """
        std_msgs/Header header
        uint32 height
        uint32 width
        PointField[] fields
        bool    is_bigendian # Is this data bigendian?
        uint32  point_step   # Length of a point in bytes
        uint32  row_step     # Length of a row in bytes
        uint8[] data         # Actual point data, size is (row_step*height)
        bool is_dense        # True if there are no invalid points""",
    "sensor_msgs/msg/PointField": """
        uint8 INT8    = 1
        uint8 UINT8   = 2
        uint8 INT16   = 3
        uint8 UINT16  = 4
        uint8 INT32   = 5
        uint8 UINT32  = 6
        uint8 FLOAT32 = 7
        uint8 FLOAT64 = 8
        string name      # Name of field
        uint32 offset    # Offset from start of point struct
        uint8  datatype  # Datatype enumeration, see above
        uint32 count     # How many elements in the field""",
    "sensor_msgs/msg/Range": """
        std_msgs/Header header # timestamp in the header is the time the ranger
        uint8 ULTRASOUND=0
        uint8 INFRARED=1
        uint8 radiation_type    # the type of radiation used by the sensor
        float32 field_of_view   # the size of the arc that the distance reading is
        float32 min_range       # minimum range value [m]
        float32 max_range       # maximum range value [m]
        float32 range           # range data [m]
        float32 variance        # variance of the range sensor""",
    "sensor_msgs/msg/RegionOfInterest": """
        uint32 x_offset  # Leftmost pixel of the ROI
        uint32 y_offset  # Topmost pixel of the ROI
        uint32 height    # Height of ROI
        uint32 width     # Width of ROI
        bool do_rectify""",
    "sensor_msgs/msg/RelativeHumidity": """
        std_msgs/Header header # timestamp of the measurement
        float64 relative_humidity    # Expression of the relative humidity
        float64 variance             # 0 is interpreted as variance unknown""",
    "sensor_msgs/msg/Temperature": """
        std_msgs/Header header # timestamp is the time the temperature was measured
        float64 temperature          # Measurement of the Temperature in Degrees Celsius.
        float64 variance             # 0 is interpreted as variance unknown.""",
    "sensor_msgs/msg/TimeReference": """
        std_msgs/Header header      # stamp is system time for which measurement was valid
        builtin_interfaces/Time time_ref  # corresponding time from this external source
        string source                     # (optional) name of time source""",
    "shape_msgs/msg/Mesh": """
        MeshTriangle[] triangles
        geometry_msgs/Point[] vertices""",
    "shape_msgs/msg/MeshTriangle": "uint32[3] vertex_indices",
    "shape_msgs/msg/Plane": "float64[4] coef",
    "shape_msgs/msg/SolidPrimitive": """
        uint8 BOX=1
        uint8 SPHERE=2
        uint8 CYLINDER=3
        uint8 CONE=4
        uint8 PRISM=5
        uint8 type
        float64[<=3] dimensions  # At no point will dimensions have a length > 3.
        uint8 BOX_X=0
        uint8 BOX_Y=1
        uint8 BOX_Z=2
        uint8 SPHERE_RADIUS=0
        uint8 CYLINDER_HEIGHT=0
        uint8 CYLINDER_RADIUS=1
        uint8 CONE_HEIGHT=0
        uint8 CONE_RADIUS=1
        uint8 PRISM_HEIGHT=0
        geometry_msgs/Polygon polygon""",
    "std_msgs/msg/Byte": "byte data",
    "std_msgs/msg/ByteMultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        byte[]            data          # array of data""",
    "std_msgs/msg/Char": "char data",
    "std_msgs/msg/Float32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        float32[]         data          # array of data""",
    "std_msgs/msg/Float64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        float64[]         data          # array of data""",
    "std_msgs/msg/Int16": "int16 data",
    "std_msgs/msg/Int16MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int16[]           data          # array of data""",
    "std_msgs/msg/Int32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int32[]           data          # array of data""",
    "std_msgs/msg/Int64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int64[]           data          # array of data""",
    "std_msgs/msg/Int8": "int8 data",
    "std_msgs/msg/Int8MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        int8[]            data          # array of data""",
    "std_msgs/msg/MultiArrayDimension": """
        string label   # label of given dimension
        uint32 size    # size of given dimension (in type units)
        uint32 stride  # stride of given dimension""",
    "std_msgs/msg/MultiArrayLayout": """
        MultiArrayDimension[] dim # Array of dimension properties
        uint32 data_offset        # padding bytes at front of data""",
    "std_msgs/msg/UInt16": "uint16 data",
    "std_msgs/msg/UInt16MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint16[]            data        # array of data""",
    "std_msgs/msg/UInt32": "uint32 data",
    "std_msgs/msg/UInt32MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint32[]          data          # array of data""",
    "std_msgs/msg/UInt64": "uint64 data",
    "std_msgs/msg/UInt64MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint64[]          data          # array of data""",
    "std_msgs/msg/UInt8MultiArray": """
        MultiArrayLayout  layout        # specification of data layout
        uint8[]           data          # array of data""",
    "stereo_msgs/msg/DisparityImage": """
        std_msgs/Header header
        sensor_msgs/Image image
        float32 f # Focal length, pixels
        float32 t # Baseline, world units
        sensor_msgs/RegionOfInterest valid_window
        float32 min_disparity
        float32 max_disparity
        float32 delta_d""",
    "test_msgs/msg/Arrays": """
        bool[3] bool_values
        byte[3] byte_values
        char[3] char_values
        float32[3] float32_values
        float64[3] float64_values
        int8[3] int8_values
        uint8[3] uint8_values
        int16[3] int16_values
        uint16[3] uint16_values
        int32[3] int32_values
        uint32[3] uint32_values
        int64[3] int64_values
        uint64[3] uint64_values
        string[3] string_values
        BasicTypes[3] basic_types_values
        Constants[3] constants_values
        Defaults[3] defaults_values
        bool[3] bool_values_default [false, true, false]
        byte[3] byte_values_default [0, 1, 255]
        char[3] char_values_default [0, 1, 127]
        float32[3] float32_values_default [1.125, 0.0, -1.125]
        float64[3] float64_values_default [3.1415, 0.0, -3.1415]
        int8[3] int8_values_default [0, 127, -128]
        uint8[3] uint8_values_default [0, 1, 255]
        int16[3] int16_values_default [0, 32767, -32768]
        uint16[3] uint16_values_default [0, 1, 65535]
        int32[3] int32_values_default [0, 2147483647, -2147483648]
        uint32[3] uint32_values_default [0, 1, 4294967295]
        int64[3] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[3] uint64_values_default [0, 1, 18446744073709551615]
        string[3] string_values_default ["", "max value", "min value"]
        int32 alignment_check""",
    "test_msgs/msg/BasicTypes": """
        bool bool_value
        byte byte_value
        char char_value
        float32 float32_value
        float64 float64_value
        int8 int8_value
        uint8 uint8_value
        int16 int16_value
        uint16 uint16_value
        int32 int32_value
        uint32 uint32_value
        int64 int64_value
        uint64 uint64_value""",
    "test_msgs/msg/BoundedPlainSequences": """
        bool[<=3] bool_values
        byte[<=3] byte_values
        char[<=3] char_values
        float32[<=3] float32_values
        float64[<=3] float64_values
        int8[<=3] int8_values
        uint8[<=3] uint8_values
        int16[<=3] int16_values
        uint16[<=3] uint16_values
        int32[<=3] int32_values
        uint32[<=3] uint32_values
        int64[<=3] int64_values
        uint64[<=3] uint64_values
        BasicTypes[<=3] basic_types_values
        Constants[<=3] constants_values
        Defaults[<=3] defaults_values
        bool[<=3] bool_values_default [false, true, false]
        byte[<=3] byte_values_default [0, 1, 255]
        char[<=3] char_values_default [0, 1, 127]
        float32[<=3] float32_values_default [1.125, 0.0, -1.125]
        float64[<=3] float64_values_default [3.1415, 0.0, -3.1415]
        int8[<=3] int8_values_default [0, 127, -128]
        uint8[<=3] uint8_values_default [0, 1, 255]
        int16[<=3] int16_values_default [0, 32767, -32768]
        uint16[<=3] uint16_values_default [0, 1, 65535]
        int32[<=3] int32_values_default [0, 2147483647, -2147483648]
        uint32[<=3] uint32_values_default [0, 1, 4294967295]
        int64[<=3] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[<=3] uint64_values_default [0, 1, 18446744073709551615]
        int32 alignment_check""",
    "test_msgs/msg/BoundedSequences": """
        bool[<=3] bool_values
        byte[<=3] byte_values
        char[<=3] char_values
        float32[<=3] float32_values
        float64[<=3] float64_values
        int8[<=3] int8_values
        uint8[<=3] uint8_values
        int16[<=3] int16_values
        uint16[<=3] uint16_values
        int32[<=3] int32_values
        uint32[<=3] uint32_values
        int64[<=3] int64_values
        uint64[<=3] uint64_values
        string[<=3] string_values
        BasicTypes[<=3] basic_types_values
        Constants[<=3] constants_values
        Defaults[<=3] defaults_values
        bool[<=3] bool_values_default [false, true, false]
        byte[<=3] byte_values_default [0, 1, 255]
        char[<=3] char_values_default [0, 1, 127]
        float32[<=3] float32_values_default [1.125, 0.0, -1.125]
        float64[<=3] float64_values_default [3.1415, 0.0, -3.1415]
        int8[<=3] int8_values_default [0, 127, -128]
        uint8[<=3] uint8_values_default [0, 1, 255]
        int16[<=3] int16_values_default [0, 32767, -32768]
        uint16[<=3] uint16_values_default [0, 1, 65535]
        int32[<=3] int32_values_default [0, 2147483647, -2147483648]
        uint32[<=3] uint32_values_default [0, 1, 4294967295]
        int64[<=3] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[<=3] uint64_values_default [0, 1, 18446744073709551615]
        string[<=3] string_values_default ["", "max value", "min value"]
        int32 alignment_check""",
    "test_msgs/msg/Builtins": """
        builtin_interfaces/Duration duration_value
        builtin_interfaces/Time time_value""",
    "test_msgs/msg/Constants": """
        bool BOOL_CONST=true
        byte BYTE_CONST=50
        char CHAR_CONST=100
        float32 FLOAT32_CONST=1.125
        float64 FLOAT64_CONST=1.125
        int8 INT8_CONST=-50
        uint8 UINT8_CONST=200
        int16 INT16_CONST=-1000
        uint16 UINT16_CONST=2000
        int32 INT32_CONST=-30000
        uint32 UINT32_CONST=60000
        int64 INT64_CONST=-40000000
        uint64 UINT64_CONST=50000000""",
    "test_msgs/msg/Defaults": """
        bool bool_value true
        byte byte_value 50
        char char_value 100
        float32 float32_value 1.125
        float64 float64_value 1.125
        int8 int8_value -50
        uint8 uint8_value 200
        int16 int16_value -1000
        uint16 uint16_value 2000
        int32 int32_value -30000
        uint32 uint32_value 60000
        int64 int64_value -40000000
        uint64 uint64_value 50000000""",
    "test_msgs/msg/Empty": "",
    "test_msgs/msg/MultiNested": """
        Arrays[3] array_of_arrays
        BoundedSequences[3] array_of_bounded_sequences
        UnboundedSequences[3] array_of_unbounded_sequences
        Arrays[<=3] bounded_sequence_of_arrays
        BoundedSequences[<=3] bounded_sequence_of_bounded_sequences
        UnboundedSequences[<=3] bounded_sequence_of_unbounded_sequences
        Arrays[] unbounded_sequence_of_arrays
        BoundedSequences[] unbounded_sequence_of_bounded_sequences
        UnboundedSequences[] unbounded_sequence_of_unbounded_sequences""",
    "test_msgs/msg/Nested": "BasicTypes basic_types_value",
    "test_msgs/msg/Strings":
        'string string_value\nstring string_value_default1 "Hello world!"\nstring string_value_default2 "Hello\'world!"\nstring string_value_default3 \'Hello"world!\'\nstring string_value_default4 \'Hello\\\'world!\'\nstring string_value_default5 "Hello\\"world!"\nstring STRING_CONST="Hello world!"\nstring<=22 bounded_string_value\nstring<=22 bounded_string_value_default1 "Hello world!"\nstring<=22 bounded_string_value_default2 "Hello\'world!"\nstring<=22 bounded_string_value_default3 \'Hello"world!\'\nstring<=22 bounded_string_value_default4 \'Hello\\\'world!\'\nstring<=22 bounded_string_value_default5 "Hello\\"world!"',
    "test_msgs/msg/UnboundedSequences": """
        bool[] bool_values
        byte[] byte_values
        char[] char_values
        float32[] float32_values
        float64[] float64_values
        int8[] int8_values
        uint8[] uint8_values
        int16[] int16_values
        uint16[] uint16_values
        int32[] int32_values
        uint32[] uint32_values
        int64[] int64_values
        uint64[] uint64_values
        string[] string_values
        BasicTypes[] basic_types_values
        Constants[] constants_values
        Defaults[] defaults_values
        bool[] bool_values_default [false, true, false]
        byte[] byte_values_default [0, 1, 255]
        char[] char_values_default [0, 1, 127]
        float32[] float32_values_default [1.125, 0.0, -1.125]
        float64[] float64_values_default [3.1415, 0.0, -3.1415]
        int8[] int8_values_default [0, 127, -128]
        uint8[] uint8_values_default [0, 1, 255]
        int16[] int16_values_default [0, 32767, -32768]
        uint16[] uint16_values_default [0, 1, 65535]
        int32[] int32_values_default [0, 2147483647, -2147483648]
        uint32[] uint32_values_default [0, 1, 4294967295]
        int64[] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[] uint64_values_default [0, 1, 18446744073709551615]
        string[] string_values_default ["", "max value", "min value"]
        int32 alignment_check""",
    "test_msgs/msg/WStrings": """
        wstring wstring_value
        wstring wstring_value_default1 "Hello world!"
        wstring wstring_value_default2 "Hellö wörld!"
        wstring wstring_value_default3 "ハローワールド"
        wstring[3] array_of_wstrings
        wstring[<=3] bounded_sequence_of_wstrings
        wstring[] unbounded_sequence_of_wstrings""",
    "trajectory_msgs/msg/JointTrajectory": """
        std_msgs/Header header
        string[] joint_names
        JointTrajectoryPoint[] points""",
    "trajectory_msgs/msg/JointTrajectoryPoint": """
        float64[] positions
        float64[] velocities
        float64[] accelerations
        float64[] effort
        builtin_interfaces/Duration time_from_start""",
    "trajectory_msgs/msg/MultiDOFJointTrajectory": """
        std_msgs/Header header
        string[] joint_names
        MultiDOFJointTrajectoryPoint[] points""",
    "trajectory_msgs/msg/MultiDOFJointTrajectoryPoint": """
        geometry_msgs/Transform[] transforms
        geometry_msgs/Twist[] velocities
        geometry_msgs/Twist[] accelerations
        builtin_interfaces/Duration time_from_start""",
    "visualization_msgs/msg/ImageMarker": """
        int32 CIRCLE=0
        int32 LINE_STRIP=1
        int32 LINE_LIST=2
        int32 POLYGON=3
        int32 POINTS=4
        int32 ADD=0
        int32 REMOVE=1
        std_msgs/Header header
        string ns
        int32 id
        int32 type
        int32 action
        geometry_msgs/Point position
        float32 scale
        std_msgs/ColorRGBA outline_color
        uint8 filled
        std_msgs/ColorRGBA fill_color
        builtin_interfaces/Duration lifetime
        geometry_msgs/Point[] points
        std_msgs/ColorRGBA[] outline_colors""",
    "visualization_msgs/msg/InteractiveMarker": """
        std_msgs/Header header
        geometry_msgs/Pose pose
        string name
        string description
        float32 scale
        MenuEntry[] menu_entries
        InteractiveMarkerControl[] controls""",
    "visualization_msgs/msg/InteractiveMarkerControl": """
        string name
        geometry_msgs/Quaternion orientation
        uint8 INHERIT = 0
        uint8 FIXED = 1
        uint8 VIEW_FACING = 2
        uint8 orientation_mode
        uint8 NONE = 0
        uint8 MENU = 1
        uint8 BUTTON = 2
        uint8 MOVE_AXIS = 3
        uint8 MOVE_PLANE = 4
        uint8 ROTATE_AXIS = 5
        uint8 MOVE_ROTATE = 6
        uint8 MOVE_3D = 7
        uint8 ROTATE_3D = 8
        uint8 MOVE_ROTATE_3D = 9
        uint8 interaction_mode
        bool always_visible
        Marker[] markers
        bool independent_marker_orientation
        string description""",
    "visualization_msgs/msg/InteractiveMarkerFeedback": """
        std_msgs/Header header
        string client_id
        string marker_name
        string control_name
        uint8 KEEP_ALIVE = 0
        uint8 POSE_UPDATE = 1
        uint8 MENU_SELECT = 2
        uint8 BUTTON_CLICK = 3
        uint8 MOUSE_DOWN = 4
        uint8 MOUSE_UP = 5
        uint8 event_type
        geometry_msgs/Pose pose
        uint32 menu_entry_id
        geometry_msgs/Point mouse_point
        bool mouse_point_valid""",
    "visualization_msgs/msg/InteractiveMarkerInit": """
        string server_id
        uint64 seq_num
        InteractiveMarker[] markers""",
    "visualization_msgs/msg/InteractiveMarkerPose": """
        std_msgs/Header header
        geometry_msgs/Pose pose
        string name""",
    "visualization_msgs/msg/InteractiveMarkerUpdate": """
        string server_id
        uint64 seq_num
        uint8 KEEP_ALIVE = 0
        uint8 UPDATE = 1
        uint8 type
        InteractiveMarker[] markers
        InteractiveMarkerPose[] poses
        string[] erases""",
    "visualization_msgs/msg/Marker": """
        int32 ARROW=0
        int32 CUBE=1
        int32 SPHERE=2
        int32 CYLINDER=3
        int32 LINE_STRIP=4
        int32 LINE_LIST=5
        int32 CUBE_LIST=6
        int32 SPHERE_LIST=7
        int32 POINTS=8
        int32 TEXT_VIEW_FACING=9
        int32 MESH_RESOURCE=10
        int32 TRIANGLE_LIST=11
        int32 ARROW_STRIP=12
        int32 ADD=0
        int32 MODIFY=0
        int32 DELETE=2
        int32 DELETEALL=3
        std_msgs/Header header
        string ns
        int32 id
        int32 type
        int32 action
        geometry_msgs/Pose pose
        geometry_msgs/Vector3 scale
        std_msgs/ColorRGBA color
        builtin_interfaces/Duration lifetime
        bool frame_locked
        geometry_msgs/Point[] points
        std_msgs/ColorRGBA[] colors
        string texture_resource
        sensor_msgs/CompressedImage texture
        UVCoordinate[] uv_coordinates
        string text
        string mesh_resource
        MeshFile mesh_file
        bool mesh_use_embedded_materials""",
    "visualization_msgs/msg/MarkerArray": "Marker[] markers",
    "visualization_msgs/msg/MenuEntry": """
        uint32 id
        uint32 parent_id
        string title
        string command
        uint8 FEEDBACK=0
        uint8 ROSRUN=1
        uint8 ROSLAUNCH=2
        uint8 command_type""",
    "visualization_msgs/msg/MeshFile": """
        string filename
        uint8[] data""",
    "visualization_msgs/msg/UVCoordinate": """
        float32 u
        float32 v""",
}

COMMON_SERVICES: dict[str, str] = {
    "example_interfaces/srv/SetBool": """
        bool data # e.g. for hardware enabling / disabling
        ---
        bool success   # indicate successful run of triggered service
        string message # informational, e.g. for error messages""",
    "example_interfaces/srv/Trigger": """
        ---
        bool success   # indicate successful run of triggered service
        string message # informational, e.g. for error messages.""",
    "nav_msgs/srv/GetMap": """
        ---
        OccupancyGrid map""",
    "nav_msgs/srv/GetPlan": """
        geometry_msgs/PoseStamped start
        geometry_msgs/PoseStamped goal
        float32 tolerance
        ---
        Path plan""",
    "nav_msgs/srv/LoadMap": """
        string map_url
        ---
        uint8 RESULT_SUCCESS=0
        uint8 RESULT_MAP_DOES_NOT_EXIST=1
        uint8 RESULT_INVALID_MAP_DATA=2
        uint8 RESULT_INVALID_MAP_METADATA=3
        uint8 RESULT_UNDEFINED_FAILURE=255
        nav_msgs/OccupancyGrid map
        uint8 result""",
    "nav_msgs/srv/SetMap": """
        nav_msgs/OccupancyGrid map
        geometry_msgs/PoseWithCovarianceStamped initial_pose
        ---
        bool success""",
    "rcl_interfaces/srv/GetLoggerLevels": """
        string[] names
        ---
        LoggerLevel[] levels""",
    "rcl_interfaces/srv/SetLoggerLevels": """
        LoggerLevel[] levels
        ---
        SetLoggerLevelsResult[] results""",
    "sensor_msgs/srv/SetCameraInfo": """
        sensor_msgs/CameraInfo camera_info # The camera_info to store
        ---
        bool success                             # True if the call succeeded
        string status_message                    # Used to give details about success""",
    "test_msgs/srv/Arrays": """
        bool[3] bool_values
        byte[3] byte_values
        char[3] char_values
        float32[3] float32_values
        float64[3] float64_values
        int8[3] int8_values
        uint8[3] uint8_values
        int16[3] int16_values
        uint16[3] uint16_values
        int32[3] int32_values
        uint32[3] uint32_values
        int64[3] int64_values
        uint64[3] uint64_values
        string[3] string_values
        BasicTypes[3] basic_types_values
        Constants[3] constants_values
        Defaults[3] defaults_values
        bool[3] bool_values_default [false, true, false]
        byte[3] byte_values_default [0, 1, 255]
        char[3] char_values_default [0, 1, 127]
        float32[3] float32_values_default [1.125, 0.0, -1.125]
        float64[3] float64_values_default [3.1415, 0.0, -3.1415]
        int8[3] int8_values_default [0, 127, -128]
        uint8[3] uint8_values_default [0, 1, 255]
        int16[3] int16_values_default [0, 32767, -32768]
        uint16[3] uint16_values_default [0, 1, 65535]
        int32[3] int32_values_default [0, 2147483647, -2147483648]
        uint32[3] uint32_values_default [0, 1, 4294967295]
        int64[3] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[3] uint64_values_default [0, 1, 18446744073709551615]
        string[3] string_values_default ["", "max value", "min value"]
        ---
        bool[3] bool_values
        byte[3] byte_values
        char[3] char_values
        float32[3] float32_values
        float64[3] float64_values
        int8[3] int8_values
        uint8[3] uint8_values
        int16[3] int16_values
        uint16[3] uint16_values
        int32[3] int32_values
        uint32[3] uint32_values
        int64[3] int64_values
        uint64[3] uint64_values
        string[3] string_values
        BasicTypes[3] basic_types_values
        Constants[3] constants_values
        Defaults[3] defaults_values
        bool[3] bool_values_default [false, true, false]
        byte[3] byte_values_default [0, 1, 255]
        char[3] char_values_default [0, 1, 127]
        float32[3] float32_values_default [1.125, 0.0, -1.125]
        float64[3] float64_values_default [3.1415, 0.0, -3.1415]
        int8[3] int8_values_default [0, 127, -128]
        uint8[3] uint8_values_default [0, 1, 255]
        int16[3] int16_values_default [0, 32767, -32768]
        uint16[3] uint16_values_default [0, 1, 65535]
        int32[3] int32_values_default [0, 2147483647, -2147483648]
        uint32[3] uint32_values_default [0, 1, 4294967295]
        int64[3] int64_values_default [0, 9223372036854775807, -9223372036854775808]
        uint64[3] uint64_values_default [0, 1, 18446744073709551615]
        string[3] string_values_default ["", "max value", "min value"]""",
    "test_msgs/srv/BasicTypes": """
        bool bool_value
        byte byte_value
        char char_value
        float32 float32_value
        float64 float64_value
        int8 int8_value
        uint8 uint8_value
        int16 int16_value
        uint16 uint16_value
        int32 int32_value
        uint32 uint32_value
        int64 int64_value
        uint64 uint64_value
        string string_value
        ---
        bool bool_value
        byte byte_value
        char char_value
        float32 float32_value
        float64 float64_value
        int8 int8_value
        uint8 uint8_value
        int16 int16_value
        uint16 uint16_value
        int32 int32_value
        uint32 uint32_value
        int64 int64_value
        uint64 uint64_value
        string string_value""",
    "test_msgs/srv/Empty": "---",
    "visualization_msgs/srv/GetInteractiveMarkers": """
        ---
        uint64 sequence_number
        InteractiveMarker[] markers""",
}

COMMON_ACTIONS: dict[str, str] = {
    "test_msgs/action/NestedMessage": """
        Builtins nested_field_no_pkg
        test_msgs/BasicTypes nested_field
        builtin_interfaces/Time nested_different_pkg
        ---
        Builtins nested_field_no_pkg
        test_msgs/BasicTypes nested_field
        builtin_interfaces/Time nested_different_pkg
        ---
        Builtins nested_field_no_pkg
        test_msgs/BasicTypes nested_field
        builtin_interfaces/Time nested_different_pkg""",
}
