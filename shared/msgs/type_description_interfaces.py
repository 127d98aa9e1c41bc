"""type_description_interfaces: REP 2011's type descriptions (TypeDescription and its parts,
TypeSource, KeyValue) and the GetTypeDescription service every node serves
(``~/get_type_description``: `zenros.type_descriptions`), with ROS 2's definitions."""

from __future__ import annotations

from typing import Annotated

import msgspec

from ..message import Message, define_service

__all__ = [
    "Field", "FieldType", "GetTypeDescription", "GetTypeDescriptionRequest",
    "GetTypeDescriptionResponse", "IndividualTypeDescription", "KeyValue", "TypeDescription",
    "TypeSource",
]

Byte = Annotated[int, msgspec.Meta(ge=0, le=255)]


class FieldType(Message):
    """A field's type: ``type_id`` (ROS 2's FIELD_TYPE_* constants: the scalar or string kind,
    plus 48 for an array, 96 a bounded sequence, 144 a sequence), the array's or bound's
    ``capacity``, a bounded string's ``string_capacity``, a nested type's name."""

    __msgtype__ = "type_description_interfaces/FieldType"
    type_id: Byte = 0
    capacity: int = 0
    string_capacity: int = 0
    nested_type_name: str = ""

    FIELD_TYPE_NOT_SET = 0
    FIELD_TYPE_NESTED_TYPE = 1


class Field(Message):
    __msgtype__ = "type_description_interfaces/Field"
    name: str = ""
    type: FieldType = msgspec.field(default_factory=FieldType)
    default_value: str = ""


class IndividualTypeDescription(Message):
    __msgtype__ = "type_description_interfaces/IndividualTypeDescription"
    type_name: str = ""
    fields: list[Field] = msgspec.field(default_factory=list)


class TypeDescription(Message):
    __msgtype__ = "type_description_interfaces/TypeDescription"
    type_description: IndividualTypeDescription = msgspec.field(
        default_factory=IndividualTypeDescription)
    referenced_type_descriptions: list[IndividualTypeDescription] = msgspec.field(
        default_factory=list)


class TypeSource(Message):
    __msgtype__ = "type_description_interfaces/TypeSource"
    type_name: str = ""
    encoding: str = ""
    raw_file_contents: str = ""


class KeyValue(Message):
    __msgtype__ = "type_description_interfaces/KeyValue"
    key: str = ""
    value: str = ""


class GetTypeDescriptionRequest(Message):
    __msgtype__ = "type_description_interfaces/GetTypeDescriptionRequest"
    type_name: str = ""
    type_hash: str = ""
    include_type_sources: bool = True


class GetTypeDescriptionResponse(Message):
    __msgtype__ = "type_description_interfaces/GetTypeDescriptionResponse"
    successful: bool = False
    failure_reason: str = ""
    type_description: TypeDescription = msgspec.field(default_factory=TypeDescription)
    type_sources: list[TypeSource] = msgspec.field(default_factory=list)
    extra_information: list[KeyValue] = msgspec.field(default_factory=list)


GetTypeDescription = define_service("type_description_interfaces/GetTypeDescription",
                                    GetTypeDescriptionRequest, GetTypeDescriptionResponse)
