// lbsolid-go-compare: checks that the profile frames a client received equal the reference's, bit
// for bit.
//
//	lbsolid-go-compare CLIENT_OUTPUT REFERENCE_OUTPUT
//
// Both files hold lines "profile STEP NY y[NY] u_x[NY]" with hexadecimal floats (the client's from
// lbsolid-go-profiles --print-hex, Go's 0x1.8p+01; the reference's from lbsolid-reference, C's
// %a 0x1.8p+1); other lines are ignored. The numbers are compared as float64 values, bit for bit,
// never as strings. Exit 0 when both hold the same frames and at least one; 1 at the first
// difference (printed); 2 on a usage or read error.
package main

import (
	"bufio"
	"fmt"
	"math"
	"os"
	"strconv"
	"strings"
)

type frame struct {
	line int
	step int64
	y    []float64
	ux   []float64
}

// readFrames parses the "profile" lines of a file.
func readFrames(path string) ([]frame, error) {
	file, err := os.Open(path)
	if err != nil {
		return nil, err
	}
	defer file.Close()
	var frames []frame
	scanner := bufio.NewScanner(file)
	scanner.Buffer(make([]byte, 1<<20), 1<<30)
	for n := 1; scanner.Scan(); n++ {
		fields := strings.Fields(scanner.Text())
		if len(fields) == 0 || fields[0] != "profile" {
			continue
		}
		bad := func(why string) error { return fmt.Errorf("%s:%d: %s", path, n, why) }
		if len(fields) < 3 {
			return nil, bad("a profile line needs STEP and NY")
		}
		step, err1 := strconv.ParseInt(fields[1], 10, 64)
		ny, err2 := strconv.Atoi(fields[2])
		if err1 != nil || err2 != nil || ny < 0 {
			return nil, bad("STEP and NY must be integers")
		}
		if len(fields) != 3+2*ny {
			return nil, bad(fmt.Sprintf("NY = %d needs %d numbers, found %d", ny, 2*ny, len(fields)-3))
		}
		values := make([]float64, 2*ny)
		for i, text := range fields[3:] {
			if values[i], err = strconv.ParseFloat(text, 64); err != nil {
				return nil, bad(fmt.Sprintf("number %d: %v", i+1, err))
			}
		}
		frames = append(frames, frame{line: n, step: step, y: values[:ny], ux: values[ny:]})
	}
	return frames, scanner.Err()
}

// firstDifference describes where two lists of values first differ as float64 bits, or is empty.
func firstDifference(name string, a, b []float64) string {
	for i := range a {
		if math.Float64bits(a[i]) != math.Float64bits(b[i]) {
			return fmt.Sprintf("%s[%d]: client %s (%v), reference %s (%v)", name, i,
				strconv.FormatFloat(a[i], 'x', -1, 64), a[i], strconv.FormatFloat(b[i], 'x', -1, 64), b[i])
		}
	}
	return ""
}

func main() {
	if len(os.Args) != 3 {
		fmt.Fprintln(os.Stderr, "usage: lbsolid-go-compare CLIENT_OUTPUT REFERENCE_OUTPUT")
		os.Exit(2)
	}
	client, err := readFrames(os.Args[1])
	if err == nil {
		var reference []frame
		if reference, err = readFrames(os.Args[2]); err == nil {
			os.Exit(compare(client, reference))
		}
	}
	fmt.Fprintf(os.Stderr, "lbsolid-go-compare: %v\n", err)
	os.Exit(2)
}

func compare(client, reference []frame) int {
	mismatch := func(format string, args ...interface{}) int {
		fmt.Fprintf(os.Stderr, "MISMATCH: "+format+"\n", args...)
		return 1
	}
	if len(client) == 0 || len(reference) == 0 {
		return mismatch("nothing to compare: the client printed %d frames, the reference %d", len(client), len(reference))
	}
	values := 0
	for k := 0; k < len(client) && k < len(reference); k++ {
		c, r := client[k], reference[k]
		if c.step != r.step {
			return mismatch("frame %d: client step %d (line %d), reference step %d (line %d)", k, c.step, c.line, r.step, r.line)
		}
		if len(c.y) != len(r.y) {
			return mismatch("frame %d (step %d): client NY %d, reference NY %d", k, c.step, len(c.y), len(r.y))
		}
		for _, d := range []string{firstDifference("y", c.y, r.y), firstDifference("u_x", c.ux, r.ux)} {
			if d != "" {
				return mismatch("frame %d (step %d): %s", k, c.step, d)
			}
		}
		values += 2 * len(c.y)
	}
	if len(client) != len(reference) {
		return mismatch("the client printed %d frames, the reference %d (the first %d agree)",
			len(client), len(reference), min(len(client), len(reference)))
	}
	fmt.Printf("%d frames (steps %d to %d), %d values: equal bit for bit\n",
		len(client), client[0].step, client[len(client)-1].step, values)
	return 0
}

func min(a, b int) int {
	if a < b {
		return a
	}
	return b
}
