// One guard's route from guardsim's route.json, for Unreal Engine (C++, header only; needs the "Json"
// module in your Build.cs). Export in centimetres with y up, e.g. one world unit = 1 m:
//   guardsim patrol LEVEL --out DIR --export route.json --axis y-up   (then multiply x, y by 100)
// Load: FGuardRoute Route; Route.Load(JsonText, 1);  each Tick: SetActorLocation(Route.PositionAt(Clock) * 100.f);
// The rule is guardsim.patrol.export.position_at: stand `wait` seconds at each waypoint, walk straight
// to the next, repeat by loop_mode (loop, ping-pong, once), start `phase` seconds along.
#pragma once

#include "CoreMinimal.h"
#include "Dom/JsonObject.h"
#include "Serialization/JsonReader.h"
#include "Serialization/JsonSerializer.h"

struct FGuardWaypoint { float X, Y, Time, Heading, Wait; };

struct FGuardRoute
{
    TArray<FGuardWaypoint> Waypoints;
    FString LoopMode;
    float Phase = 0.f;
    float Period = 0.f;

    bool Load(const FString& JsonText, int32 Guard)
    {
        TSharedPtr<FJsonObject> Root;
        if (!FJsonSerializer::Deserialize(TJsonReaderFactory<>::Create(JsonText), Root) || !Root.IsValid()) return false;
        Root->TryGetNumberField(TEXT("period_seconds"), Period);
        const TArray<TSharedPtr<FJsonValue>>& Guards = Root->GetArrayField(TEXT("guards"));
        if (!Guards.IsValidIndex(Guard - 1)) return false;
        const TSharedPtr<FJsonObject> G = Guards[Guard - 1]->AsObject();
        LoopMode = G->GetStringField(TEXT("loop_mode"));
        Phase = G->GetNumberField(TEXT("phase"));
        for (const TSharedPtr<FJsonValue>& Value : G->GetArrayField(TEXT("waypoints")))
        {
            const TSharedPtr<FJsonObject> W = Value->AsObject();
            Waypoints.Add({(float)W->GetNumberField(TEXT("x")), (float)W->GetNumberField(TEXT("y")),
                           (float)W->GetNumberField(TEXT("time")), (float)W->GetNumberField(TEXT("heading")),
                           (float)W->GetNumberField(TEXT("wait"))});
        }
        return Waypoints.Num() > 0;
    }

    FVector PositionAt(float Seconds) const
    {
        const int32 Last = Waypoints.Num() - 1;
        float T = Seconds + Phase;
        if (LoopMode != TEXT("once")) T = FMath::Fmod(FMath::Fmod(T, Period) + Period, Period);
        if (LoopMode == TEXT("ping-pong"))
        {
            const float Turn = Waypoints[Last].Time + Waypoints[Last].Wait;
            if (T > Turn) T = Waypoints[Last].Time - (T - Turn);  // the walk back mirrors the walk out
        }
        int32 I = Last;
        while (I > 0 && Waypoints[I].Time > T) --I;
        const FGuardWaypoint& Here = Waypoints[I];
        const float Leave = Here.Time + Here.Wait;
        if (I == Last || T <= Leave) return FVector(Here.X, Here.Y, 0.f);
        const FGuardWaypoint& Next = Waypoints[I + 1];
        const float Share = (T - Leave) / (Next.Time - Leave);
        return FVector(FMath::Lerp(Here.X, Next.X, Share), FMath::Lerp(Here.Y, Next.Y, Share), 0.f);
    }
};
