package main

import (
	"fmt"
	"os"
	"strings"

	"google.golang.org/protobuf/encoding/protojson"
	"google.golang.org/protobuf/encoding/prototext"

	lbsolidv1 "lbsolid/v1"
)

// readScenario reads a Scenario from a file: JSON when its first non-blank character is '{',
// protobuf text format (.textproto, '#' comments allowed) otherwise.
func readScenario(path string) (*lbsolidv1.Scenario, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, fmt.Errorf("cannot read the scenario: %v", err)
	}
	scenario := &lbsolidv1.Scenario{}
	if strings.HasPrefix(strings.TrimSpace(string(data)), "{") {
		err = protojson.Unmarshal(data, scenario)
	} else {
		err = prototext.Unmarshal(data, scenario)
	}
	if err != nil {
		return nil, fmt.Errorf("%s: not a valid lbsolid.v1.Scenario: %v", path, err)
	}
	return scenario, nil
}
