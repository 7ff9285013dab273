package main

import (
	"fmt"

	"google.golang.org/grpc/encoding"
	"google.golang.org/protobuf/proto"
)

// grpc-go 1.33 (Debian 12's golang-google-grpc-dev) marshals messages through
// github.com/golang/protobuf, which Debian 12 ships at v1.3 (golang-github-golang-protobuf-1-3-dev).
// That version predates the APIv2 messages protoc-gen-go 1.28 generates and panics on them
// ("protobuf tag not enough fields in Session.state"). This codec, registered under grpc's default
// name "proto", replaces it and marshals with google.golang.org/protobuf (APIv2) instead; the wire
// format is the same.
type protoV2Codec struct{}

func (protoV2Codec) Marshal(v interface{}) ([]byte, error) {
	m, ok := v.(proto.Message)
	if !ok {
		return nil, fmt.Errorf("cannot marshal %T: not a protobuf message", v)
	}
	return proto.Marshal(m)
}

func (protoV2Codec) Unmarshal(data []byte, v interface{}) error {
	m, ok := v.(proto.Message)
	if !ok {
		return fmt.Errorf("cannot unmarshal into %T: not a protobuf message", v)
	}
	return proto.Unmarshal(data, m)
}

func (protoV2Codec) Name() string { return "proto" }

func init() { encoding.RegisterCodec(protoV2Codec{}) }
