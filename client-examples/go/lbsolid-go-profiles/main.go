// lbsolid-go-profiles: a small Go client of lbsolidd. It creates a session from a scenario file,
// watches its velocity profile u_x(y) losslessly, runs it for a number of steps, prints every frame
// and reports how the session ended.
//
//	lbsolid-go-profiles --address HOST:PORT --scenario FILE --steps N --every K [--print-hex]
//	                    [--timeout S] [--stream-timeout S] [--outputs DIR]
//	                    [--tls-ca FILE [--tls-cert FILE --tls-key FILE]] [--token-file FILE]
//
// Exit codes, as the lbsolid CLI's: 0 the session reached DONE; 1 it FAILED or was CANCELLED;
// 2 bad input (usage, unreadable or invalid scenario, INVALID_ARGUMENT, NOT_FOUND, ...);
// 3 daemon unreachable or a transient error (UNAVAILABLE, DEADLINE_EXCEEDED, ...).
package main

import (
	"context"
	"errors"
	"flag"
	"fmt"
	"io"
	"os"
	"time"

	"google.golang.org/grpc"

	lbsolidv1 "lbsolid/v1"
)

type options struct {
	address       string
	scenario      string
	steps         int64
	every         int64
	printHex      bool
	timeout       time.Duration // deadline of each unary RPC (and of connecting)
	streamTimeout time.Duration // deadline of the whole profile stream
	outputs       string        // where to copy the daemon's recorded outputs ("": none recorded)
	tlsCA         string
	tlsCert       string
	tlsKey        string
	tokenFile     string
}

func parseOptions() (options, error) {
	var o options
	var timeout, streamTimeout float64
	flags := flag.NewFlagSet("lbsolid-go-profiles", flag.ContinueOnError)
	flags.StringVar(&o.address, "address", "127.0.0.1:50051", "the daemon's address, HOST:PORT")
	flags.StringVar(&o.scenario, "scenario", "", "scenario file: protobuf text, or JSON when it starts with '{' (required)")
	flags.Int64Var(&o.steps, "steps", 0, "steps to run, >= 1 (required)")
	flags.Int64Var(&o.every, "every", 0, "steps between profile frames, >= 1 (required)")
	flags.BoolVar(&o.printHex, "print-hex", false, "print one line per frame, 'profile STEP NY y... u_x...', in hexadecimal floats (exact)")
	flags.Float64Var(&timeout, "timeout", 30, "deadline of each unary call and of connecting, seconds")
	flags.Float64Var(&streamTimeout, "stream-timeout", 3600, "deadline of the profile stream (the whole run), seconds")
	flags.StringVar(&o.outputs, "outputs", "", "have the daemon record the profiles and final fields, and copy them into this directory after the run")
	flags.StringVar(&o.tlsCA, "tls-ca", "", "TLS: trust the daemon's certificate if this CA (PEM) signed it")
	flags.StringVar(&o.tlsCert, "tls-cert", "", "a client certificate (PEM) for mutual TLS, with --tls-key")
	flags.StringVar(&o.tlsKey, "tls-key", "", "the key of --tls-cert (PEM)")
	flags.StringVar(&o.tokenFile, "token-file", "", "send the token in this file's first line (default $LBSOLID_TOKEN)")
	if err := flags.Parse(os.Args[1:]); err != nil {
		return o, err
	}
	switch {
	case flags.NArg() > 0:
		return o, fmt.Errorf("unexpected argument %q", flags.Arg(0))
	case o.scenario == "":
		return o, errors.New("--scenario is required")
	case o.steps < 1:
		return o, fmt.Errorf("--steps must be at least 1, got %d", o.steps)
	case o.every < 1:
		return o, fmt.Errorf("--every must be at least 1, got %d", o.every)
	case timeout <= 0 || streamTimeout <= 0:
		return o, errors.New("--timeout and --stream-timeout must be positive")
	}
	o.timeout = time.Duration(timeout * float64(time.Second))
	o.streamTimeout = time.Duration(streamTimeout * float64(time.Second))
	return o, nil
}

func main() {
	o, err := parseOptions()
	if err != nil {
		fmt.Fprintf(os.Stderr, "lbsolid-go-profiles: %v\n", err)
		os.Exit(exitBadInput)
	}
	os.Exit(run(o))
}

// run does the work and returns the exit code.
func run(o options) int {
	scenario, err := readScenario(o.scenario)
	if err != nil {
		return fail(exitBadInput, "%v", err)
	}

	if o.outputs != "" && scenario.GetOutputs() == nil {
		scenario.Outputs = &lbsolidv1.Outputs{ProfileEvery: o.every, FinalFields: true}
	}
	dial, err := dialOptions(o)
	if err != nil {
		return fail(exitBadInput, "%v", err)
	}
	dialCtx, cancelDial := context.WithTimeout(context.Background(), o.timeout)
	conn, err := grpc.DialContext(dialCtx, o.address, append(dial, grpc.WithBlock())...)
	cancelDial()
	if err != nil {
		return fail(exitTransient, "cannot connect to lbsolidd at %s within %v: %v", o.address, o.timeout, err)
	}
	defer conn.Close()
	client := lbsolidv1.NewSimulationClient(conn)

	// 1. Create the session.
	ctx, cancel := context.WithTimeout(context.Background(), o.timeout)
	session, err := client.CreateSession(ctx, &lbsolidv1.CreateSessionRequest{Scenario: scenario})
	cancel()
	if err != nil {
		return rpcFailure("CreateSession", err)
	}
	id := session.GetId()
	fmt.Fprintf(os.Stderr, "session %s created: %q, %d cells, %d particles, stages %v\n",
		id, session.GetName(), session.GetCells(), session.GetParticles(), session.GetStages())
	for _, w := range session.GetWarnings() {
		fmt.Fprintf(os.Stderr, "warning: %s\n", w)
	}

	// 2. Subscribe losslessly and wait for the first frame (the current state), so that no frame of
	// the run can be missed.
	streamCtx, cancelStream := context.WithTimeout(context.Background(), o.streamTimeout)
	defer cancelStream()
	stream, err := client.WatchProfiles(streamCtx, &lbsolidv1.WatchProfilesRequest{
		SessionId: id,
		Every:     o.every,
		Delivery:  lbsolidv1.DeliveryMode_DELIVERY_MODE_EVERY_FRAME,
	})
	if err != nil {
		return rpcFailure("WatchProfiles", err)
	}
	first, err := stream.Recv()
	if err != nil {
		if err == io.EOF {
			return fail(exitTransient, "WatchProfiles: the stream ended before its first frame")
		}
		return rpcFailure("WatchProfiles", err)
	}
	printer := newFramePrinter(os.Stdout, o.printHex)
	if err := printer.print(first); err != nil {
		return fail(exitTransient, "%v", err)
	}

	// 3. Run: asynchronous, returns at once.
	ctx, cancel = context.WithTimeout(context.Background(), o.timeout)
	session, err = client.Run(ctx, &lbsolidv1.RunRequest{SessionId: id, Steps: o.steps})
	cancel()
	if err != nil {
		return rpcFailure("Run", err)
	}
	fmt.Fprintf(os.Stderr, "session %s running to step %d\n", id, session.GetTargetStep())

	// 4. Every frame until the stream ends (the session reached DONE, FAILED or CANCELLED).
	frames := 1
	for {
		frame, err := stream.Recv()
		if err == io.EOF {
			break
		}
		if err != nil {
			return rpcFailure("WatchProfiles", err)
		}
		if err := printer.print(frame); err != nil {
			return fail(exitTransient, "%v", err)
		}
		frames++
	}
	if err := printer.flush(); err != nil {
		return fail(exitTransient, "writing the frames: %v", err)
	}

	// 5. How did it end?
	ctx, cancel = context.WithTimeout(context.Background(), o.timeout)
	session, err = client.GetSession(ctx, &lbsolidv1.GetSessionRequest{SessionId: id})
	cancel()
	if err != nil {
		return rpcFailure("GetSession", err)
	}
	if o.outputs != "" && session.GetState() == lbsolidv1.SessionState_SESSION_STATE_DONE {
		if code := downloadOutputs(client, id, o.outputs, o.timeout); code != exitDone {
			return code
		}
	}
	return reportEnd(session, frames)
}
