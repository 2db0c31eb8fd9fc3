// REQUEST_DATA_STREAM as a ground station sends it to ArduPilot (component 1): ArduPilot sends
// the stream's messages at `rateHz` from then on. Used by guided_flight_plan.cjs and
// status_texts.cjs.
'use strict';
const { common } = require('node-mavlink');

function requestDataStream(send, sysid, streamId, rateHz) {
  const streams = new common.RequestDataStream();
  streams.targetSystem = sysid;
  streams.targetComponent = 1;
  streams.reqStreamId = streamId;
  streams.reqMessageRate = rateHz;
  streams.startStop = 1;
  send(streams);
}

module.exports = { requestDataStream };
